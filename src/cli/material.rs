//! `viscoslide material ...`

use crate::error::Result;

#[derive(Debug, clap::Subcommand)]
pub enum MaterialCommand {
    /// Print the creep spectrum and a table of E(w).
    Show(super::ConfigArgs),
}

pub fn run(cmd: MaterialCommand) -> Result<()> {
    match cmd {
        MaterialCommand::Show(args) => {
            let cfg = args.load()?;
            let m = cfg.material()?.build(&cfg.base_dir)?;
            println!("{m:?}");
            Ok(())
        }
    }
}
