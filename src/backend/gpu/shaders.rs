//! The WGSL sources of `shaders/`, embedded at compile time. WGSL has no
//! include directive: every kernel is compiled with the shared helpers of
//! [`SHARED`] prepended, then the kernel's own [`includes`] (helpers only
//! some kernels need, e.g. the Green's function of `shared/green.wgsl`), then
//! the kernel. [`validate`] runs naga's front end and
//! validator on a source, so a broken shader fails a test instead of a solve.

/// Shared helpers, in the order they are prepended.
pub const SHARED: &[(&str, &str)] = &[
    (
        "shared/common.wgsl",
        include_str!("../../../shaders/shared/common.wgsl"),
    ),
    (
        "shared/complex.wgsl",
        include_str!("../../../shaders/shared/complex.wgsl"),
    ),
    (
        "shared/reduce.wgsl",
        include_str!("../../../shaders/shared/reduce.wgsl"),
    ),
    (
        "shared/scan.wgsl",
        include_str!("../../../shaders/shared/scan.wgsl"),
    ),
];

/// The steady-sliding Green's function of a square source cell (paper Eq. 4
/// and Eq. 6), with the creep-term binding 1; included by the coefficient
/// kernels only.
pub const GREEN: (&str, &str) = (
    "shared/green.wgsl",
    include_str!("../../../shaders/shared/green.wgsl"),
);

/// The workgroup-memory FFT blocks, included by the shared-memory FFT
/// passes only.
pub const FFT_BLOCK: (&str, &str) = (
    "shared/fft_block.wgsl",
    include_str!("../../../shaders/shared/fft_block.wgsl"),
);

/// Largest workgroup block in complex f32 elements (64 KiB).
pub const MAX_SHARED: usize = 8192;

/// Complex f32 elements of the workgroup array of [`FFT_BLOCK`] for `storage_bytes` of
/// workgroup memory: the largest power of two that fits, at most
/// [`MAX_SHARED`].
pub fn shared_elements(storage_bytes: u64) -> usize {
    let n = (storage_bytes / 8).min(MAX_SHARED as u64);
    if n == 0 {
        0
    } else {
        1usize << (63 - n.leading_zeros())
    }
}

/// The line of [`FFT_BLOCK`] that sizes its workgroup array.
const FFT_SHARED_LINE: &str = "const FFT_SHARED: u32 = 2048u;";

/// `source` with the workgroup block of [`FFT_BLOCK`] sized to `elements`
/// complex values (a power of two); unchanged for other kernels.
pub fn with_fft_shared(source: &str, elements: usize) -> String {
    if elements == 0 {
        return source.to_string();
    }
    source.replace(
        FFT_SHARED_LINE,
        &format!("const FFT_SHARED: u32 = {elements}u;"),
    )
}

/// Helpers included by kernel `name` after [`SHARED`], in order.
pub fn includes(name: &str) -> &'static [(&'static str, &'static str)] {
    match name {
        "fft_radix.wgsl" | "fft_radix_product.wgsl" => std::slice::from_ref(&FFT_BLOCK),
        "coefficients.wgsl"
        | "adaptive_coefficients.wgsl"
        | "adaptive_matvec.wgsl"
        | "level_table.wgsl" => std::slice::from_ref(&GREEN),
        _ => &[],
    }
}

macro_rules! kernels {
    ($($name:literal),* $(,)?) => {
        /// Kernel files (without the shared prelude), by file name.
        pub const KERNELS: &[(&str, &str)] = &[
            $(($name, include_str!(concat!("../../../shaders/", $name)))),*
        ];
    };
}

kernels!(
    "axpy.wgsl",
    "combine.wgsl",
    "scale.wgsl",
    "add_scalar.wgsl",
    "gather.wgsl",
    "scatter.wgsl",
    "gap.wgsl",
    "active_set.wgsl",
    "complementarity.wgsl",
    "dot.wgsl",
    "sum.wgsl",
    "compact_count.wgsl",
    "compact_scan.wgsl",
    "compact_write.wgsl",
    "fft_load.wgsl",
    "fft_pass.wgsl",
    "spectral_product.wgsl",
    "spectral_product_f16.wgsl",
    "fft_extract.wgsl",
    "fft_radix.wgsl",
    "fft_radix_product.wgsl",
    "fft_split.wgsl",
    "fft_merge.wgsl",
    "coefficients.wgsl",
    "adaptive_coefficients.wgsl",
    "adaptive_matvec.wgsl",
    "adaptive_sum.wgsl",
    "level_table.wgsl",
    "level_box_sum.wgsl",
    "level_matvec.wgsl",
);

/// The source of kernel file `name` (e.g. `axpy.wgsl`) with the shared
/// prelude and its own includes.
pub fn compose(name: &str) -> Option<String> {
    let body = KERNELS.iter().find(|(n, _)| *n == name)?.1;
    let mut s = String::new();
    for (file, src) in SHARED.iter().chain(includes(name)) {
        s.push_str("// ---- ");
        s.push_str(file);
        s.push('\n');
        s.push_str(src);
    }
    s.push_str("// ---- ");
    s.push_str(name);
    s.push('\n');
    s.push_str(body);
    Some(s)
}

/// Parse and validate WGSL with naga; the error is naga's report.
pub fn validate(source: &str) -> Result<(), String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(source))?;
    Ok(())
}
