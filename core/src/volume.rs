//! Volume views over caller-owned voxel slices.

use crate::each::Each;
use crate::error::Error;
use crate::voxel::{Voxel, VoxelFault};

/// Largest size of one volume axis (2²⁴, so every voxel coordinate is exact in `f32`).
pub const MAX_DIM: usize = 1 << 24;

/// A validated view of a 3D grid of voxels in a caller-owned slice.
///
/// Voxel `(x, y, z)` is at index `x + nx·(y + ny·z)`; voxel centres sit at integer
/// coordinates, so the volume covers the box `[−½, n − ½]` on each axis. Reconstruction
/// clamps to the edge: a position outside the grid reads the nearest edge voxel.
///
/// The opacity of a voxel is defined for the reference distance `d′`
/// ([`reference_distance`](Self::reference_distance), one voxel by default).
///
/// ```
/// use volsample::{Volume, StraightU8, Error};
/// let voxels = [StraightU8([255, 0, 0, 128]); 8];
/// let vol = Volume::new(&voxels, [2, 2, 2])?;
/// assert_eq!(vol.dims(), [2, 2, 2]);
/// assert_eq!(Volume::new(&voxels, [2, 2, 3]).unwrap_err(),
///            Error::LengthMismatch { expected: 12, actual: 8 });
/// # Ok::<(), Error>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Volume<'a, V> {
    data: &'a [V],
    dims: [usize; 3],
    d_ref: f32,
}

impl<'a, V: Voxel> Volume<'a, V> {
    /// Wraps `data` as an `nx × ny × nz` volume with reference distance 1 voxel.
    ///
    /// # Errors
    /// [`Error::ZeroDimension`], [`Error::DimensionTooLarge`], [`Error::LengthMismatch`], and for
    /// the first invalid voxel [`Error::NonFiniteVoxel`], [`Error::VoxelOutOfRange`] or
    /// [`Error::ColorExceedsOpacity`].
    pub fn new(data: &'a [V], dims: [usize; 3]) -> Result<Self, Error> {
        for (axis, &n) in (0u8..).zip(dims.iter()) {
            if n == 0 {
                return Err(Error::ZeroDimension { axis });
            }
            if n > MAX_DIM {
                return Err(Error::DimensionTooLarge);
            }
        }
        let [nx, ny, nz] = dims;
        let expected = nx
            .checked_mul(ny)
            .and_then(|p| p.checked_mul(nz))
            .ok_or(Error::DimensionTooLarge)?;
        if data.len() != expected {
            return Err(Error::LengthMismatch {
                expected,
                actual: data.len(),
            });
        }
        for (index, v) in data.iter().enumerate() {
            v.check().map_err(|fault| match fault {
                VoxelFault::NonFinite => Error::NonFiniteVoxel { index },
                VoxelFault::OutOfRange => Error::VoxelOutOfRange { index },
                VoxelFault::ColorExceedsOpacity => Error::ColorExceedsOpacity { index },
            })?;
        }
        Ok(Self {
            data,
            dims,
            d_ref: 1.0,
        })
    }

    /// Sets the reference distance `d′` for which the voxel opacities are defined
    /// (in voxel units).
    ///
    /// # Errors
    /// [`Error::InvalidReferenceDistance`] unless `d_ref` is finite and positive.
    pub fn with_reference_distance(mut self, d_ref: f32) -> Result<Self, Error> {
        if !(d_ref.is_finite() && d_ref > 0.0) {
            return Err(Error::InvalidReferenceDistance);
        }
        self.d_ref = d_ref;
        Ok(self)
    }
}

impl<'a, V: Voxel> Volume<'a, V> {
    /// `[nx, ny, nz]`.
    #[inline]
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// The reference distance `d′` (voxel units).
    #[inline]
    pub fn reference_distance(&self) -> f32 {
        self.d_ref
    }

    /// The voxel slice.
    #[inline]
    pub fn data(&self) -> &'a [V] {
        self.data
    }

    /// Prefetches ([`arch::prefetch`](crate::arch::prefetch)) the voxels of the cell at
    /// `pos` (voxel units; clamped into the grid by [`clamp_index`](Self::clamp_index), NaN
    /// as 0): the first voxel of each of its four rows along x, where a trilinear sample there
    /// reads (its second voxel is the next one). A hint: nothing is read.
    #[inline(always)]
    pub(crate) fn prefetch_cell(&self, pos: [f32; 3]) {
        let [nx, ny, _] = self.dims;
        // (`as` saturates, NaN to 0; `clamp_index` brings the rest into the grid.)
        let [x, y, z] = pos.each(|p| p as isize);
        for (dy, dz) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let [cx, cy, cz] = self.clamp_index([x, y.saturating_add(dy), z.saturating_add(dz)]);
            if let Some(v) = self.data.get(cx + nx * (cy + ny * cz)) {
                crate::arch::prefetch(v);
            }
        }
    }

    /// The same grid over `data`, another view of this volume's voxels (as
    /// [`Voxel::as_extinction_f32`] gives): not validated again, so only for the data itself.
    /// (A shorter slice could not make a read panic, since every read is checked, but would
    /// read wrong voxels.)
    #[inline(always)]
    pub(crate) fn with_data<U>(&self, data: &'a [U]) -> Volume<'a, U> {
        Volume {
            data,
            dims: self.dims,
            d_ref: self.d_ref,
        }
    }

    /// The voxel at `(x, y, z)`, or `None` outside the grid.
    #[inline]
    pub fn get(&self, x: usize, y: usize, z: usize) -> Option<V> {
        let [nx, ny, nz] = self.dims;
        if x >= nx || y >= ny || z >= nz {
            return None;
        }
        self.data.get(x + nx * (y + ny * z)).copied()
    }

    /// The voxel at `(x, y, z)` with each coordinate clamped into the grid (clamp-to-edge).
    #[inline(always)]
    pub fn fetch_clamped(&self, x: isize, y: isize, z: isize) -> V {
        let [nx, ny, _] = self.dims;
        let [cx, cy, cz] = self.clamp_index([x, y, z]);
        // In range by the clamp and the validated length, so `get` always hits.
        self.data
            .get(cx + nx * (cy + ny * cz))
            .copied()
            .unwrap_or(V::TRANSPARENT)
    }

    /// The 8 voxels of the trilinear cell whose low corner is `(x, y, z)`, in tap order
    /// (tap `i` at `(x + (i & 1), y + ((i >> 1) & 1), z + (i >> 2))`), each read by
    /// [`fetch_clamped`](Self::fetch_clamped) (`x + 1` saturating): the clamped gather of
    /// the float and integer trilinear filters, defined for every corner.
    #[inline(always)]
    pub fn cell_clamped(&self, x: isize, y: isize, z: isize) -> [V; 8] {
        let (x1, y1, z1) = (
            x.saturating_add(1),
            y.saturating_add(1),
            z.saturating_add(1),
        );
        [
            self.fetch_clamped(x, y, z),
            self.fetch_clamped(x1, y, z),
            self.fetch_clamped(x, y1, z),
            self.fetch_clamped(x1, y1, z),
            self.fetch_clamped(x, y, z1),
            self.fetch_clamped(x1, y, z1),
            self.fetch_clamped(x, y1, z1),
            self.fetch_clamped(x1, y1, z1),
        ]
    }

    /// The 8 voxels of the trilinear cell whose low corner is `(x, y, z)`, in tap order
    /// (tap `i` at `(x + (i & 1), y + ((i >> 1) & 1), z + (i >> 2))`), or `None` unless the
    /// whole cell lies inside the grid (`x + 1 < nx`, and so on).
    ///
    /// The interior fast path of the trilinear filters: one bounds check per pair of
    /// neighbouring voxels instead of a clamp per coordinate and tap. Where it returns
    /// `Some`, the taps equal those of [`fetch_clamped`](Self::fetch_clamped).
    #[inline(always)]
    pub fn cell(&self, x: usize, y: usize, z: usize) -> Option<[V; 8]> {
        self.cell_map(x, y, z, |v| *v)
    }

    /// [`cell`](Self::cell) with `f` applied to each voxel in place (no copy of the voxels
    /// first): `f` of the taps in tap order, or `None` where `cell` gives `None`.
    #[inline(always)]
    pub(crate) fn cell_map<R>(
        &self,
        x: usize,
        y: usize,
        z: usize,
        f: impl Fn(&V) -> R,
    ) -> Option<[R; 8]> {
        let [nx, ny, nz] = self.dims;
        // Every axis is at least 1 voxel long (validated), so `n - 1` cannot wrap.
        if x >= nx - 1 || y >= ny - 1 || z >= nz - 1 {
            return None;
        }
        let plane = nx * ny;
        // One slice check for the whole cell: the rows start at 0, nx, plane and plane + nx
        // of it. Splitting at those offsets (each row at least 2 long, since nx ≥ 2 here)
        // lets the optimiser drop the per-row checks.
        let cell = self.data.get(x + nx * (y + ny * z)..)?;
        let (row0, rest) = cell.split_at_checked(nx)?;
        let (row1, rest) = rest.split_at_checked(plane - nx)?;
        let (row2, row3) = rest.split_at_checked(nx)?;
        let [v0, v1] = row0.first_chunk::<2>()?;
        let [v2, v3] = row1.first_chunk::<2>()?;
        let [v4, v5] = row2.first_chunk::<2>()?;
        let [v6, v7] = row3.first_chunk::<2>()?;
        Some([f(v0), f(v1), f(v2), f(v3), f(v4), f(v5), f(v6), f(v7)])
    }

    /// Clamps a signed voxel coordinate into the grid.
    #[inline(always)]
    pub fn clamp_index(&self, i: [isize; 3]) -> [usize; 3] {
        let mut out = [0usize; 3];
        for ((o, &i), &n) in out.iter_mut().zip(i.iter()).zip(self.dims.iter()) {
            *o = if i <= 0 { 0 } else { (i as usize).min(n - 1) };
        }
        out
    }
}
