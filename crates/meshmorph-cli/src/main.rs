//! `meshmorph`: gradient-domain shape animation from the command line.
//!
//! A thin layer over the `meshmorph` library: each subcommand parses its
//! arguments, reads files, reports progress and calls the library.

/// `println!` that never panics: a closed or full stdout is said once the
/// run is over ([`output::print_line`]).
macro_rules! say {
    () => {
        $crate::output::print_line(format_args!(""))
    };
    ($($arg:tt)*) => {
        $crate::output::print_line(format_args!($($arg)*))
    };
}

/// `eprintln!` that never panics: with stderr closed (`2>&1 | head -1`)
/// the message is lost, and the run (or the thread saying it, such as the
/// one that stops the run on Ctrl-C) goes on.
macro_rules! tell {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod allocator;
mod animation;
mod batch_file;
mod blend;
mod correspond;
mod demo;
mod drawings;
mod expressions;
mod frame_chunks;
mod gltf;
mod interpolate;
mod kept_frames;
mod manual;
mod memory;
mod output;
mod outputs;
mod pick;
mod picture_morph;
mod pictures;
mod progress;
mod threads;
mod transfer;

use std::process::ExitCode;

use clap::{CommandFactory, Parser, Subcommand};

#[global_allocator]
static ALLOCATOR: allocator::Refusing = allocator::Refusing;

/// Gradient-domain shape animation on triangle meshes.
///
/// As-rigid-as-possible shape interpolation (Alexa, Cohen-Or, Levin 2000;
/// Baxter, Barla, Anjyo 2008) and deformation transfer (Sumner, Popovic
/// 2004).
#[derive(Debug, Parser)]
#[command(name = "meshmorph", version, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    // `interpolate` and `blend` take their help from their arguments' docs.
    Interpolate(interpolate::Args),
    Blend(blend::Args),
    /// Carry the poses of a source mesh over to a different target mesh.
    Transfer(transfer::TransferArgs),
    /// Compute the triangle correspondence between two meshes and save it.
    Correspond(correspond::CorrespondCommand),
    /// Put facial expressions (the 52 ARKit shapes) on a head from a few landmarks.
    Expressions(expressions::Args),
    /// Pick marker pairs on two meshes in the browser and save them.
    Pick(pick::Args),
    /// Run on built-in procedural shapes and write frames and pictures.
    Demo(demo::Args),
    /// Print a shell completion script, e.g.
    /// `meshmorph completions bash > ~/.local/share/bash-completion/completions/meshmorph`.
    Completions {
        /// The shell.
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
    /// Print the manual page (roff), e.g. `meshmorph man | man -l -`.
    Man(manual::ManArgs),
}

impl Command {
    /// How the command draws its pictures, if it draws.
    #[cfg(test)]
    fn draw(&self) -> Option<&pictures::DrawArgs> {
        match self {
            Command::Interpolate(a) => Some(&a.frames.pictures.draw),
            Command::Blend(a) => Some(&a.pictures.draw),
            Command::Transfer(a) => Some(&a.pictures.draw),
            Command::Correspond(a) => Some(&a.pictures.draw),
            Command::Demo(a) => Some(&a.draw),
            Command::Expressions(a) => Some(&a.pictures.draw),
            Command::Pick(_) | Command::Completions { .. } | Command::Man(_) => None,
        }
    }

    /// Whether the report was asked for as JSON (`--json`).
    fn json(&self) -> bool {
        match self {
            Command::Interpolate(a) => a.json,
            Command::Blend(a) => a.json,
            Command::Transfer(a) => a.json,
            Command::Correspond(a) => a.json,
            Command::Demo(a) => a.json,
            Command::Expressions(a) => a.json,
            Command::Pick(_) | Command::Completions { .. } | Command::Man(_) => false,
        }
    }
}

impl Command {
    /// Refuses a `--gltf` named `.gltf` or `.vrm` where the file is made
    /// from scratch as a binary glTF (interpolate, blend, a transfer into a
    /// target that is not itself glTF): only a transfer into a glTF or VRM
    /// target writes the target's own kind of file.
    fn new_gltf_named_glb(&self) -> std::result::Result<(), String> {
        let (gltf, into_gltf) = match self {
            Command::Interpolate(a) => (&a.frames.gltf.gltf, false),
            Command::Blend(a) => (&a.gltf.gltf, false),
            Command::Transfer(a) => (&a.gltf.gltf, a.writes_into_gltf_target()),
            _ => return Ok(()),
        };
        match gltf {
            Some(path) if !into_gltf => {
                pictures::file_named(&path.to_string_lossy(), "glb", "binary glTF").map(drop)
            }
            _ => Ok(()),
        }
    }
}

/// Runs the command line `words` (the program's name first) in this
/// process, as `main` runs it: the demo's steps that are a user's command.
fn run_words(words: Vec<std::ffi::OsString>) -> anyhow::Result<()> {
    let cli = Cli::try_parse_from(words)?;
    match cli.command {
        Command::Interpolate(args) => interpolate::run(&args),
        other => anyhow::bail!("not a command the demo runs: {other:?}"),
    }
}

fn main() -> ExitCode {
    memory::share_one_heap();
    allocator::reserve();
    let cli = Cli::parse();
    if let Err(message) = cli.command.new_gltf_named_glb() {
        Cli::command()
            .error(clap::error::ErrorKind::ValueValidation, message)
            .exit();
    }
    threads::start_pool();
    let json = cli.command.json();
    outputs::interrupted_as_json(json);
    let result = match cli.command {
        Command::Interpolate(args) => interpolate::run(&args),
        Command::Blend(args) => blend::run(&args),
        Command::Transfer(args) => transfer::run(&args),
        Command::Correspond(args) => correspond::run_correspond(&args),
        Command::Expressions(args) => expressions::run(&args),
        Command::Pick(args) => pick::run(&args),
        Command::Demo(args) => demo::run(&args),
        Command::Completions { shell } => {
            manual::completions(Cli::command(), shell);
            Ok(())
        }
        Command::Man(args) => manual::man(Cli::command(), &args),
    };
    let status = match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            tell!("error: {e:#}");
            if json {
                output::print_json_error(&format!("{e:#}"), 1);
            }
            return ExitCode::FAILURE;
        }
    };
    // The run succeeded and its outputs are in place; only its report (or
    // the printed page) did not get through.
    if let Err(e) = output::finish_stdout() {
        tell!("error: printing on stdout failed ({e}); every file the run writes was written");
        return ExitCode::FAILURE;
    }
    status
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_command_that_draws_takes_the_same_picture_options() {
        let commands: [&[&str]; 5] = [
            &["interpolate", "a.obj", "b.obj", "-o", "out"],
            &[
                "transfer",
                "--source-ref",
                "s.obj",
                "--target-ref",
                "t.obj",
                "-o",
                "out",
                "p.obj",
            ],
            &["blend", "base.obj", "--shape", "s.obj=1", "-o", "out.obj"],
            &[
                "correspond",
                "--source-ref",
                "s.obj",
                "--target-ref",
                "t.obj",
                "-o",
                "c.corr",
            ],
            &["demo"],
        ];
        for command in commands {
            let draw = |extra: &[&str]| {
                let words = ["meshmorph"].iter().chain(command).chain(extra);
                let cli = Cli::try_parse_from(words).unwrap_or_else(|e| panic!("{command:?}: {e}"));
                let d = cli.command.draw().expect("draws").clone();
                (d.size, d.gif_width, d.gif_height, d.fps, d.no_boomerang)
            };
            assert_eq!(draw(&[]), (640, None, None, 25.0, false), "{command:?}");
            let given = [
                "--size",
                "800",
                "--gif-width",
                "300",
                "--gif-height",
                "200",
                "--fps",
                "12",
                "--no-boomerang",
            ];
            assert_eq!(
                draw(&given),
                (800, Some(300), Some(200), 12.0, true),
                "{command:?}"
            );
        }
        for command in ["completions", "man"] {
            let cli = Cli::try_parse_from(["meshmorph", command, "bash"]);
            assert!(cli.map_or(true, |c| c.command.draw().is_none()));
        }
    }
}
