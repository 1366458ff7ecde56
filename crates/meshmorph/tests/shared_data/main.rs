//! The library on the real meshes of ../shared/data beside the repository:
//! the elephant, man and bar of other ARAP implementations, Sumner's horse,
//! camel, face and head. A fresh clone has no such folder: a check whose
//! folder is absent is reported as ignored, naming it, and fails in CI
//! (`CI=true`), which has the data (`needs.rs`).

#[path = "../library/common.rs"]
mod common;
mod expressions;
mod interpolate;
mod io;
mod needs;
mod surfaces;
mod transfer;

use std::path::PathBuf;

/// A check: its name, the folder of ../shared/data it reads, its body.
type Check = (&'static str, &'static str, fn(PathBuf));

fn main() {
    let args = libtest_mimic::Arguments::from_args();
    let checks: [Check; 9] = [
        ("io::shared_data_meshes", "", io::shared_data_meshes),
        (
            "interpolate::real_2d_meshes_interpolate_without_flips",
            "2d",
            interpolate::real_2d_meshes_interpolate_without_flips,
        ),
        (
            "surfaces::horse_poses_interpolate_without_inversions",
            "dt/horse-camel/horse-poses",
            surfaces::horse_poses_interpolate_without_inversions,
        ),
        (
            "transfer::horse_poses_transfer_to_the_camel_close_to_sumners",
            "dt/horse-camel",
            transfer::horse_poses_transfer_to_the_camel_close_to_sumners,
        ),
        (
            "transfer::horse_poses_transfer_to_the_camel_aligned",
            "dt/horse-camel",
            transfer::horse_poses_transfer_to_the_camel_aligned,
        ),
        (
            "transfer::horse_and_camel_are_their_own_mirror_images_about_their_files_middle_plane",
            "dt/horse-camel",
            transfer::horse_and_camel_are_their_own_mirror_images_about_their_files_middle_plane,
        ),
        (
            "transfer::the_face_masks_cry_transfers_to_the_head_close_to_sumners",
            "dt/face-head",
            transfer::the_face_masks_cry_transfers_to_the_head_close_to_sumners,
        ),
        (
            "expressions::sumners_head_opens_its_jaw_each_lip_moving_as_a_whole",
            "dt/face-head",
            expressions::sumners_head_opens_its_jaw_each_lip_moving_as_a_whole,
        ),
        (
            "transfer::the_camels_nonmanifold_edges_and_boundaries_are_handled",
            "dt/horse-camel",
            transfer::the_camels_nonmanifold_edges_and_boundaries_are_handled,
        ),
    ];
    let trials = checks
        .into_iter()
        .map(|(name, folder, check)| needs::trial(name, needs::shared_data(folder), check))
        .collect();
    libtest_mimic::run(&args, trials).exit();
}
