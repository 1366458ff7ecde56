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

fn main() {
    let args = libtest_mimic::Arguments::from_args();
    let mut checks = gltf_clients::checks();
    checks.extend(pick_page::checks());
    checks.extend(drawing_players::checks());
    let mut trials = browser::trials(checks);
    trials.push(needs::trial(
        "readme::readme_commands_name_the_shared_data_by_its_paths",
        needs::shared_data(""),
        readme::readme_commands_name_the_shared_data_by_its_paths,
    ));
    libtest_mimic::run(&args, trials).exit();
}
