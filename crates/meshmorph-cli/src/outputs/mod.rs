//! Every file a command writes goes through here: one plan of all the
//! outputs of a run, checked before any work, staged, and moved into place
//! only when the whole run has succeeded.
//!
//! ```text
//! let mut plan = Plan::new();
//! plan.input(&args.source, "source mesh");          // every file the run reads
//! let frames = plan.frames(&dir, times.len(), "obj"); // dir/frame_0000.obj, ...
//! let gif = plan.file(&gif_path, "animation");       // any single file
//! let run = plan.prepare()?;   // clashes refused, folders created, Ctrl-C armed
//! run.write(gif, |path| meshmorph::render::write_gif_2d(path, ...).map_err(Into::into))?;
//! run.commit()?;               // all outputs into place, surplus frames removed
//! ```
//!
//! The guarantees, for every command:
//!
//! - **No input is written.** [`Plan::prepare`] compares every output with
//!   every input and with every other output by resolved path (symbolic
//!   links and `..` followed, the parent folder made canonical) and, where a
//!   file already sits at the output path, by device and inode (hard links).
//!   A clash is refused before any work, naming both paths. So is an output
//!   slot that holds a folder, an output folder that is a file, and an
//!   output folder that does not take new files (tried by creating and
//!   removing an output's staged file there).
//! - **All or nothing.** [`Staging::write`] hands the writer a temporary
//!   name (`.meshmorph-<pid>-<token>-<n>.part`, the token random for each
//!   run) in the output's own folder, or, in a folder the run creates, the
//!   final name inside that folder staged whole under a hidden name
//!   (`.meshmorph-<pid>-<token>-<j>.folder`); [`Staging::write_to`] makes
//!   the file itself at that path, new, and hands over a writer: no
//!   temporary name and rename per file. Nothing at the user's path changes
//!   until [`Staging::commit`], which moves every staged file into place
//!   (keeping a second name of each file it replaces until all moves
//!   succeeded, and putting them back if one fails). Nothing opens an
//!   existing path for writing: files are created new, and reach their
//!   names by renames. A run that fails or is dropped before committing
//!   removes its staged files and the folders it created, and nothing
//!   else.
//! - **Side files.** [`Staging::also_reads`] adds the files found while
//!   reading (material libraries, textures) to the inputs, before any write.
//! - **One commit at a time per folder**: the moves and the sweep below
//!   hold an advisory lock on each output folder.
//! - **Surplus frames.** After a successful commit, files in a frame folder
//!   named exactly as meshmorph names frames (`frame_` followed by four or
//!   more digits, then `.obj`, `.off`, `.ply`, `.stl` or `.svg`) that this
//!   run did not write are removed, so that the folder holds one
//!   animation. Inputs and any other file are left alone.
//! - **Interrupts.** On SIGINT, SIGTERM, SIGHUP, SIGQUIT (and the other
//!   signals that would end the process), writes in progress finish, then
//!   every staged file and created folder is removed and the process exits
//!   (status 128 + the signal's number) saying nothing was written: an
//!   interrupted run leaves the output folders as they were. An interrupt
//!   during the commit waits for it and says every output is in place. A
//!   failed allocation ([`abandon`]) removes the staged files too.
//! - **Forced stops.** A run killed by a signal it cannot catch (SIGKILL,
//!   the out-of-memory killer) leaves its staged files. On Linux, a later
//!   run removes, in each folder it writes to, the staged, temporary and
//!   second-name files whose process no longer runs (no `/proc/<pid>`),
//!   and says how many and how large; elsewhere they stay.
//! - **Messages name the user's path**, never a temporary one.

mod interrupt;
mod plan;
mod resolve;
mod staging;
mod stale;
mod surplus;

pub use interrupt::{abandon, interrupted_as_json};
pub use plan::{check_runs, Output, Plan};
pub use staging::Staging;
pub use surplus::frame_path;
