//! `meshmorph completions` and `meshmorph man`: shell completions and manual
//! pages generated from the command-line definitions.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Command;

/// Print the manual page, or write one page per command to a folder.
#[derive(Debug, clap::Args)]
pub struct ManArgs {
    /// Write meshmorph.1 and a page per subcommand (meshmorph-transfer.1,
    /// ...) to DIR instead of printing meshmorph.1.
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,
}

/// Prints a completion script for `shell`.
pub fn completions(mut cmd: Command, shell: clap_complete::Shell) {
    clap_complete::generate(shell, &mut cmd, "meshmorph", &mut std::io::stdout());
}

/// Prints the manual page, or writes every page to `args.dir`.
pub fn man(cmd: Command, args: &ManArgs) -> Result<()> {
    let Some(dir) = &args.dir else {
        return clap_mangen::Man::new(cmd)
            .render(&mut std::io::stdout())
            .context("printing the manual page");
    };
    std::fs::create_dir_all(dir).with_context(|| format!("creating `{}`", dir.display()))?;
    let mut cmd = cmd.disable_help_subcommand(true);
    cmd.build();
    write_pages(&cmd, dir)
}

/// Writes the page of `cmd` and of each of its subcommands.
fn write_pages(cmd: &Command, dir: &Path) -> Result<()> {
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        write_pages(sub, dir)?;
    }
    let page = clap_mangen::Man::new(cmd.clone());
    let path = dir.join(page.get_filename());
    meshmorph::io::write_atomic(&path, |w| page.render(w))?;
    println!("{}", path.display());
    Ok(())
}
