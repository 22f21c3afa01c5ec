//! The per-ray cell cache of the float trilinear ray marcher ([`TapCache`](crate::TapCache)).

use crate::volume::Volume;
use crate::voxel::Voxel;

/// What a trilinear kernel derived from the 8 taps of the last interior cell a ray sampled
/// (its two faces of constant `z`, each of type `F`), and where that cell is.
///
/// `faces[flip]` is the bottom face (taps 0–3), the other the top one (taps 4–7), so moving
/// one cell along `z` rewrites one face and keeps the shared one.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FaceCache<F> {
    /// Linear index of the cell's low corner, or `usize::MAX` for none.
    base: usize,
    faces: [F; 2],
    flip: bool,
}

impl<F: Copy> FaceCache<F> {
    /// An empty cache (`empty` fills the faces until the first cell is read).
    pub(crate) const fn new(empty: F) -> Self {
        Self {
            base: usize::MAX,
            faces: [empty; 2],
            flip: false,
        }
    }

    /// The bottom and the top face.
    #[inline(always)]
    fn faces(&self) -> (&F, &F) {
        let [a, b] = &self.faces;
        if self.flip {
            (b, a)
        } else {
            (a, b)
        }
    }

    /// The bottom and the top face, mutably.
    #[inline(always)]
    fn faces_mut(&mut self) -> (&mut F, &mut F) {
        let [a, b] = &mut self.faces;
        if self.flip {
            (b, a)
        } else {
            (a, b)
        }
    }

    /// The faces of the interior cell with low corner `base` (linear index), made by `face`
    /// from 4 voxels each unless the cache holds them: from the cell below or above in `z`
    /// it keeps the shared face and reads the other 4 taps, otherwise all 8. `None` (cache
    /// unchanged) only if the slice does not hold the cell, which an interior cell of a
    /// validated volume never is.
    #[inline(always)]
    pub(crate) fn cell<V: Voxel>(
        &mut self,
        vol: &Volume<'_, V>,
        base: usize,
        face: impl Fn([V; 4]) -> F,
    ) -> Option<(&F, &F)> {
        if base != self.base {
            let [nx, ny, _] = vol.dims();
            let plane = nx * ny;
            if base == self.base.wrapping_add(plane) {
                // One cell up: the old top face is the new bottom face.
                let top = vol.face_at(base + plane)?;
                self.flip = !self.flip;
                *self.faces_mut().1 = face(top);
            } else if base.wrapping_add(plane) == self.base {
                // One cell down: the old bottom face is the new top face.
                let bottom = vol.face_at(base)?;
                self.flip = !self.flip;
                *self.faces_mut().0 = face(bottom);
            } else {
                let (bottom, top) = (vol.face_at(base)?, vol.face_at(base + plane)?);
                let (lo, hi) = self.faces_mut();
                *lo = face(bottom);
                *hi = face(top);
            }
            self.base = base;
        }
        Some(self.faces())
    }
}
