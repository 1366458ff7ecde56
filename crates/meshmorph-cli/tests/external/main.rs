//! The command line's checks that need what a fresh clone does not have:
//! real glTF clients (`gltf_clients.rs`), the page of `pick` in Chromium
//! (`pick_page.rs`), drawing morphs in lottie-web and as animated SVG
//! (`drawing_players.rs`; all through `browser.rs`) and the meshes of ../shared/data
//! (`readme.rs`). Where they are missing a check is reported as ignored,
//! naming what is missing, and fails in CI (`CI=true`), which has them; the
//! harness is libtest-mimic's, which can tell at run time (`needs.rs`,
//! shared with the library's `shared_data` binary).

mod browser;
mod drawing_players;
mod gltf_clients;
#[path = "../../../meshmorph/tests/shared_data/needs.rs"]
mod needs;
mod pick_page;
mod readme;

/// The checks that take longest (10 to 20 s each in CI; 2 to 6 s for the
/// others), longest first.
const LONGEST_FIRST: [&str; 4] = [
    "pick_page::guided_by_the_template_the_landmarks_are_placed_and_previewed",
    "gltf_clients::three_js_in_chromium_draws_the_animation_moving",
    "gltf_clients::three_js_in_chromium_reads_written_back_glb_and_vrm",
    "gltf_clients::blenders_importer_reads_every_glb",
];

fn main() {
    let args = libtest_mimic::Arguments::from_args();
    let mut checks = gltf_clients::checks();
    checks.extend(pick_page::checks());
    checks.extend(drawing_players::checks());
    // The longest checks start first (the rest take a few seconds each), so
    // that the test threads end together rather than one waiting on the
    // other's last long check.
    checks.sort_by_key(|(name, ..)| {
        LONGEST_FIRST
            .iter()
            .position(|n| n == name)
            .unwrap_or(LONGEST_FIRST.len())
    });
    let mut trials = browser::trials(checks);
    trials.push(needs::trial(
        "readme::readme_commands_name_the_shared_data_by_its_paths",
        needs::shared_data(""),
        readme::readme_commands_name_the_shared_data_by_its_paths,
    ));
    libtest_mimic::run(&args, trials).exit();
}
