//! The sampling step and its start phase.

use crate::error::Error;

/// The sampling step `d` (voxel units) and the start phase in `[0, 1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Step {
    pub(super) d: f32,
    pub(super) phase: f32,
}

impl Step {
    /// Step `d`, phase 0.
    ///
    /// # Errors
    /// [`Error::InvalidStep`] unless `d` is finite and positive.
    pub fn new(d: f32) -> Result<Self, Error> {
        if d.is_finite() && d > 0.0 {
            Ok(Self { d, phase: 0.0 })
        } else {
            Err(Error::InvalidStep)
        }
    }

    /// Sets the start phase (samples at `(k + phase)·d`).
    ///
    /// # Errors
    /// [`Error::InvalidPhase`] outside `[0, 1)`.
    pub fn with_phase(mut self, phase: f32) -> Result<Self, Error> {
        if (0.0..1.0).contains(&phase) {
            self.phase = phase;
            Ok(self)
        } else {
            Err(Error::InvalidPhase)
        }
    }

    /// `d`.
    pub fn d(&self) -> f32 {
        self.d
    }

    /// The phase.
    pub fn phase(&self) -> f32 {
        self.phase
    }
}
