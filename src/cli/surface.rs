//! `viscoslide surface ...`

use crate::error::Result;

#[derive(Debug, clap::Subcommand)]
pub enum SurfaceCommand {
    /// Print statistics of a height map.
    Stats {
        /// `.npy` height map.
        file: std::path::PathBuf,
        /// Side along x [m].
        #[arg(long)]
        length: f64,
    },
}

pub fn run(cmd: SurfaceCommand) -> Result<()> {
    match cmd {
        SurfaceCommand::Stats { file, length } => {
            let (nx, ny, _) = crate::io::npy::read_2d(&file)?;
            println!("{nx} x {ny}, cell {} m", length / nx as f64);
            Ok(())
        }
    }
}
