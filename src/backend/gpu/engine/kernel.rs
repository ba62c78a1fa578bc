//! The compute kernels of the engine, one per file in `shaders/`, and the
//! access and splitting of their storage bindings.

/// The compute kernels, one per file in `shaders/`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kernel {
    Axpy,
    Combine,
    Scale,
    AddScalar,
    Gather,
    Scatter,
    Gap,
    ActiveSet,
    Complementarity,
    Dot,
    Sum,
    CompactCount,
    CompactScan,
    CompactWrite,
    FftLoad,
    FftPass,
    SpectralProduct,
    SpectralProductF16,
    FftExtract,
    FftRadix,
    FftRadixProduct,
    FftSplit,
    FftMerge,
    Coefficients,
    AdaptiveCoefficients,
    AdaptiveMatvec,
    AdaptiveSum,
    LevelTable,
    LevelBoxSum,
    LevelMatvec,
}

impl Kernel {
    /// File in `shaders/`.
    pub fn file(self) -> &'static str {
        match self {
            Kernel::Axpy => "axpy.wgsl",
            Kernel::Combine => "combine.wgsl",
            Kernel::Scale => "scale.wgsl",
            Kernel::AddScalar => "add_scalar.wgsl",
            Kernel::Gather => "gather.wgsl",
            Kernel::Scatter => "scatter.wgsl",
            Kernel::Gap => "gap.wgsl",
            Kernel::ActiveSet => "active_set.wgsl",
            Kernel::Complementarity => "complementarity.wgsl",
            Kernel::Dot => "dot.wgsl",
            Kernel::Sum => "sum.wgsl",
            Kernel::CompactCount => "compact_count.wgsl",
            Kernel::CompactScan => "compact_scan.wgsl",
            Kernel::CompactWrite => "compact_write.wgsl",
            Kernel::FftLoad => "fft_load.wgsl",
            Kernel::FftPass => "fft_pass.wgsl",
            Kernel::SpectralProduct => "spectral_product.wgsl",
            Kernel::SpectralProductF16 => "spectral_product_f16.wgsl",
            Kernel::FftExtract => "fft_extract.wgsl",
            Kernel::FftRadix => "fft_radix.wgsl",
            Kernel::FftRadixProduct => "fft_radix_product.wgsl",
            Kernel::FftSplit => "fft_split.wgsl",
            Kernel::FftMerge => "fft_merge.wgsl",
            Kernel::Coefficients => "coefficients.wgsl",
            Kernel::AdaptiveCoefficients => "adaptive_coefficients.wgsl",
            Kernel::AdaptiveMatvec => "adaptive_matvec.wgsl",
            Kernel::AdaptiveSum => "adaptive_sum.wgsl",
            Kernel::LevelTable => "level_table.wgsl",
            Kernel::LevelBoxSum => "level_box_sum.wgsl",
            Kernel::LevelMatvec => "level_matvec.wgsl",
        }
    }

    /// Access of the storage bindings 1, 2, ... (`true`: read-only).
    pub(super) fn storage(self) -> &'static [bool] {
        const R: bool = true;
        const W: bool = false;
        match self {
            Kernel::Axpy => &[R, W],
            Kernel::Combine => &[R, R, R, R, W],
            Kernel::Scale | Kernel::AddScalar => &[W],
            Kernel::Gather | Kernel::Scatter => &[R, R, W],
            Kernel::Gap => &[R, R, W],
            Kernel::ActiveSet => &[R, R, W, W],
            Kernel::Complementarity => &[R, R, W],
            Kernel::Dot => &[R, R, R, R, R, W],
            Kernel::Sum => &[R, W],
            Kernel::CompactCount => &[R, W],
            Kernel::CompactScan => &[W],
            Kernel::CompactWrite => &[R, R, W],
            Kernel::FftLoad => &[R, W, W],
            Kernel::FftPass => &[R, W, R],
            Kernel::SpectralProduct | Kernel::SpectralProductF16 => &[W, R],
            Kernel::FftExtract => &[R, W],
            Kernel::FftRadix | Kernel::FftSplit | Kernel::FftMerge => &[R, W, R],
            Kernel::FftRadixProduct => &[R, W, R, R],
            Kernel::Coefficients => &[R, W],
            Kernel::AdaptiveCoefficients => &[R, R, W],
            Kernel::AdaptiveMatvec => &[R, R, R, R, R, W],
            Kernel::AdaptiveSum => &[R, R, W],
            Kernel::LevelTable => &[R, W],
            Kernel::LevelBoxSum => &[R, W],
            Kernel::LevelMatvec => &[R, R, R, R, R, R, W],
        }
    }

    /// Storage bindings (as in `Kernel::storage`) that may be larger
    /// than one binding: the shader reaches them only through the
    /// accessors of [`super::super::split`].
    pub fn splittable(self) -> &'static [bool] {
        const S: bool = true;
        const N: bool = false;
        match self {
            Kernel::Axpy => &[S, S],
            Kernel::Combine => &[S, S, S, S, S],
            Kernel::Scale | Kernel::AddScalar => &[S],
            Kernel::Gather | Kernel::Scatter | Kernel::Gap => &[S, S, S],
            Kernel::ActiveSet => &[S, S, S, S],
            Kernel::Complementarity => &[S, S, S],
            Kernel::Dot => &[S, S, S, S, S, S],
            Kernel::Sum => &[S, S],
            Kernel::CompactCount => &[S, N],
            Kernel::CompactWrite => &[S, N, S],
            Kernel::FftRadix | Kernel::FftSplit | Kernel::FftMerge => &[S, S, N],
            Kernel::FftRadixProduct => &[S, S, N, S],
            Kernel::FftLoad => &[S, S, S],
            Kernel::FftPass => &[S, S, N],
            Kernel::SpectralProduct | Kernel::SpectralProductF16 => &[S, S],
            Kernel::FftExtract => &[S, S],
            Kernel::Coefficients => &[N, S],
            Kernel::AdaptiveCoefficients => &[N, S, S],
            Kernel::AdaptiveMatvec => &[N, S, S, S, N, S],
            Kernel::AdaptiveSum => &[S, N, S],
            Kernel::LevelTable => &[N, S],
            Kernel::LevelBoxSum => &[S, S],
            Kernel::LevelMatvec => &[S, S, S, S, S, N, S],
            _ => &[],
        }
    }
}
