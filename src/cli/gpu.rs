//! `viscoslide gpu`: list adapters.

use crate::backend::gpu;
use crate::error::Result;

#[derive(Debug, clap::Args)]
pub struct GpuArgs {
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: GpuArgs) -> Result<()> {
    let adapters = gpu::list_adapters();
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&adapters).expect("serialisable")
        );
        return Ok(());
    }
    if adapters.is_empty() {
        println!(
            "no GPU adapter found (install a Vulkan driver; on CPU-only Linux: apt-get install mesa-vulkan-drivers libvulkan1)"
        );
    }
    for (k, a) in adapters.iter().enumerate() {
        println!("[{k}] {a}");
    }
    Ok(())
}
