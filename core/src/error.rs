//! The one error type of the crate.
//!
//! Every constructor validates its input once and returns one of these values instead of
//! panicking; the kernels that run afterwards cannot fail.

use core::fmt;

/// What was wrong with the input given to a constructor.
///
/// The enum is `#[non_exhaustive]`: later versions may report new kinds of bad input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Error {
    /// The voxel slice does not hold `nx·ny·nz` voxels.
    LengthMismatch {
        /// `nx·ny·nz`.
        expected: usize,
        /// The slice length given.
        actual: usize,
    },
    /// A volume dimension is zero.
    ZeroDimension {
        /// The axis (0 = x, 1 = y, 2 = z).
        axis: u8,
    },
    /// A dimension exceeds [`MAX_DIM`](crate::volume::MAX_DIM), or `nx·ny·nz` overflows `usize`.
    DimensionTooLarge,
    /// A float voxel holds NaN or ±∞.
    NonFiniteVoxel {
        /// Linear index `x + nx·(y + ny·z)` of the first bad voxel.
        index: usize,
    },
    /// A float voxel holds a value outside its range (color or opacity outside `[0, 1]`,
    /// negative or too large extinction).
    VoxelOutOfRange {
        /// Linear index of the first bad voxel.
        index: usize,
    },
    /// An associated (premultiplied or extinction-weighted) voxel has a color channel larger
    /// than its opacity (or extinction): no straight color in `[0, 1]` gives it.
    ColorExceedsOpacity {
        /// Linear index of the first bad voxel.
        index: usize,
    },
    /// The reference (opacity unit) distance `d′` is not finite and positive.
    InvalidReferenceDistance,
    /// The sampling step `d` is not finite and positive.
    InvalidStep,
    /// The start phase is not in `[0, 1)`.
    InvalidPhase,
    /// The early-termination threshold is not in `(0, 1]`.
    InvalidThreshold,
    /// A background color is not a valid associated color (finite, in `[0, 1]`, `C ≤ A`).
    InvalidBackground,
    /// A transfer function has no control point.
    TransferFunctionEmpty,
    /// More control points than the transfer function's capacity.
    TransferFunctionFull,
    /// Transfer-function control points are not strictly increasing in their scalar value.
    TransferFunctionUnsorted,
    /// A transfer-function entry is NaN, ±∞ or (for color and opacity) outside `[0, 1]`.
    TransferFunctionValue,
    /// A camera has a non-finite parameter, a zero direction, an `up` vector parallel to the
    /// view direction, a non-positive extent or a field of view outside `(0, π)`.
    InvalidCamera,
    /// A ray has a non-finite origin or a zero or non-finite direction.
    InvalidRay,
    /// The image slice does not hold `width·height` pixels.
    ImageSizeMismatch {
        /// `width·height`.
        expected: usize,
        /// The slice length given.
        actual: usize,
    },
    /// The image has zero width or height.
    EmptyImage,
    /// A band of image rows (`render_rows_into`) does not lie in the image.
    RowsOutsideImage {
        /// The band's first row.
        first: usize,
        /// Its number of rows.
        rows: usize,
        /// The image height.
        height: usize,
    },
    /// An isosurface classifier has a non-finite value, an opacity outside `[0, 1]` or a
    /// non-positive thickness.
    InvalidClassifier,
    /// A light has a non-finite or zero direction or a negative coefficient.
    InvalidLight,
    /// The step is so small that a ray through the volume would take more than
    /// [`MAX_SAMPLES_PER_RAY`](crate::render::MAX_SAMPLES_PER_RAY) samples.
    TooManySamples,
    /// A fixed-point sample position has a fraction `≥ 2^F` or does not fit in `u32`.
    InvalidPosition,
    /// An integer sample does not satisfy `C̃ ≤ α ≤ ONE`.
    InvalidIntSample,
    /// A downsampling filter's outer weight `a` is not finite or not in `[0, ½]`.
    InvalidDownsampleFilter,
    /// An output buffer (a downsampled level or a mipmap chain: voxels; an occupancy grid:
    /// bytes) does not hold the number of elements it needs.
    OutputLengthMismatch {
        /// The voxels needed.
        expected: usize,
        /// The buffer length given.
        actual: usize,
    },
    /// An occupancy grid's brick size exponent exceeds
    /// [`MAX_BRICK_LOG2`](crate::skip::MAX_BRICK_LOG2).
    InvalidBrickSize,
    /// An instruction-set name that is not one of [`Isa::NAMES`](crate::Isa::NAMES).
    UnknownIsa,
    /// An instruction set this CPU (or target) does not have.
    IsaUnavailable,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::LengthMismatch { expected, actual } => write!(
                f,
                "voxel slice holds {actual} voxels but the dimensions need {expected}"
            ),
            Error::ZeroDimension { axis } => write!(f, "volume dimension {axis} is zero"),
            Error::DimensionTooLarge => {
                f.write_str("a volume dimension is too large or the voxel count overflows")
            }
            Error::NonFiniteVoxel { index } => write!(f, "voxel {index} is NaN or infinite"),
            Error::VoxelOutOfRange { index } => write!(f, "voxel {index} is out of range"),
            Error::ColorExceedsOpacity { index } => {
                write!(f, "voxel {index} has an associated color above its opacity")
            }
            Error::InvalidReferenceDistance => {
                f.write_str("the reference distance must be finite and positive")
            }
            Error::InvalidStep => f.write_str("the sampling step must be finite and positive"),
            Error::InvalidPhase => f.write_str("the start phase must lie in [0, 1)"),
            Error::UnknownIsa => f.write_str("unknown instruction set (known: baseline, avx2)"),
            Error::IsaUnavailable => f.write_str("this CPU does not have that instruction set"),
            Error::InvalidThreshold => {
                f.write_str("the early-termination threshold must lie in (0, 1]")
            }
            Error::InvalidBackground => {
                f.write_str("the background must be a finite associated color with C <= A <= 1")
            }
            Error::TransferFunctionEmpty => f.write_str("the transfer function has no points"),
            Error::TransferFunctionFull => {
                f.write_str("the transfer function has more points than its capacity")
            }
            Error::TransferFunctionUnsorted => {
                f.write_str("transfer-function points must be strictly increasing")
            }
            Error::TransferFunctionValue => {
                f.write_str("a transfer-function entry is non-finite or outside [0, 1]")
            }
            Error::InvalidCamera => f.write_str("the camera parameters are invalid"),
            Error::InvalidRay => f.write_str("the ray origin or direction is invalid"),
            Error::ImageSizeMismatch { expected, actual } => write!(
                f,
                "image slice holds {actual} pixels but width*height is {expected}"
            ),
            Error::EmptyImage => f.write_str("the image has zero width or height"),
            Error::RowsOutsideImage {
                first,
                rows,
                height,
            } => write!(
                f,
                "rows {first}..{first}+{rows} do not lie in an image of {height} rows"
            ),
            Error::InvalidClassifier => f.write_str(
                "the isosurface classifier needs a finite isovalue, opacity in [0, 1], thickness > 0",
            ),
            Error::InvalidLight => f.write_str(
                "the light needs a finite non-zero direction and non-negative coefficients",
            ),
            Error::TooManySamples => {
                f.write_str("the step is too small: a ray would take too many samples")
            }
            Error::InvalidPosition => {
                f.write_str("the fixed-point position has a fraction out of range or overflows")
            }
            Error::InvalidIntSample => {
                f.write_str("the integer sample breaks C <= A <= ONE")
            }
            Error::InvalidDownsampleFilter => {
                f.write_str("the downsampling filter weight a must be finite and in [0, 1/2]")
            }
            Error::OutputLengthMismatch { expected, actual } => write!(
                f,
                "output buffer holds {actual} elements but needs {expected}"
            ),
            Error::InvalidBrickSize => f.write_str("the brick size exponent must be at most 8"),
        }
    }
}

impl core::error::Error for Error {}
