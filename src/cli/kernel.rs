//! `viscoslide kernel ...`

use crate::error::{Error, Result};

#[derive(Debug, clap::Args)]
pub struct KernelArgs {
    #[arg(long)]
    pub config: std::path::PathBuf,
}

pub fn run(_args: KernelArgs) -> Result<()> {
    Err(Error::Invalid("kernel evaluation is not built yet".into()))
}
