//! `meshmorph completions` and `meshmorph man`: shell completions and manual
//! pages generated from the command-line definitions.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Command;

use crate::outputs::Plan;

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
    let mut script = Vec::new();
    clap_complete::generate(shell, &mut cmd, "meshmorph", &mut script);
    crate::output::print_bytes(&script);
}

/// Prints the manual page, or writes every page to `args.dir`.
pub fn man(cmd: Command, args: &ManArgs) -> Result<()> {
    let Some(dir) = &args.dir else {
        let mut page = Vec::new();
        clap_mangen::Man::new(cmd)
            .render(&mut page)
            .context("rendering the manual page")?;
        crate::output::print_bytes(&page);
        return Ok(());
    };
    let mut cmd = cmd.disable_help_subcommand(true);
    cmd.build();
    let mut pages = Vec::new();
    collect_pages(&cmd, &mut pages);
    // Through the outputs' rules: all the pages or none, never over a file
    // that is not a page.
    let mut plan = Plan::new();
    let planned: Vec<_> = pages
        .iter()
        .map(|page| plan.file(&dir.join(page.get_filename()), "manual page"))
        .collect();
    let staging = plan.prepare()?;
    for (page, output) in pages.iter().zip(&planned) {
        staging.write(*output, |path| {
            Ok(meshmorph::io::write_atomic(path, |w| page.render(w))?)
        })?;
    }
    staging.commit()?;
    for page in &pages {
        say!("{}", dir.join(page.get_filename()).display());
    }
    Ok(())
}

/// The page of `cmd` and of each of its subcommands, subcommands first.
fn collect_pages(cmd: &Command, pages: &mut Vec<clap_mangen::Man>) {
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        collect_pages(sub, pages);
    }
    pages.push(clap_mangen::Man::new(cmd.clone()));
}
