//! Generated stand-ins for real scans: a CT-like head (8-bit, a skull-like shell around soft
//! tissue) for the renderer's benchmarks, and an asymmetric phantom for orientation tests.

use volsample::ControlPoint;

/// Scalar of air in the CT-like head.
pub const CT_AIR: u8 = 0;
/// Scalar of the scalp and soft tissue.
pub const CT_SOFT: u8 = 80;
/// Scalar of the brain.
pub const CT_BRAIN: u8 = 100;
/// Scalar of the fluid-filled ventricles.
pub const CT_FLUID: u8 = 60;
/// Scalar of bone.
pub const CT_BONE: u8 = 230;

/// A CT-like head of `n³` 8-bit voxels (x fastest): an ellipsoid of scalp and soft tissue
/// around a bony shell (the skull, thicker at the base), brain inside with two ventricles
/// and a little deterministic texture; air outside. Values: [`CT_AIR`], [`CT_SOFT`],
/// [`CT_BONE`], [`CT_BRAIN`], [`CT_FLUID`] plus texture of ±6.
pub fn ct_head(n: usize) -> Vec<u8> {
    let c = (n as f32 - 1.0) * 0.5;
    let s = n as f32;
    // Semi-axes of the head (x left-right, y front-back, z up-down), fractions of n.
    let (ax, ay, az) = (0.38 * s, 0.46 * s, 0.44 * s);
    let mut v = vec![CT_AIR; n * n * n];
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let (px, py, pz) = (x as f32 - c, y as f32 - c, z as f32 - c);
                let r = ((px / ax).powi(2) + (py / ay).powi(2) + (pz / az).powi(2)).sqrt();
                // The skull is thicker towards the base (negative z).
                let bone_in = 0.86 - 0.04 * (-pz / az).max(0.0);
                let value = if r > 1.0 {
                    CT_AIR
                } else if r > 0.95 {
                    CT_SOFT
                } else if r > bone_in {
                    CT_BONE
                } else {
                    let ventricle = |sx: f32| {
                        ((px - sx * s) / (0.05 * s)).powi(2)
                            + ((py - 0.02 * s) / (0.14 * s)).powi(2)
                            + ((pz - 0.06 * s) / (0.07 * s)).powi(2)
                            < 1.0
                    };
                    if ventricle(0.06) || ventricle(-0.06) {
                        CT_FLUID
                    } else {
                        // A smooth deterministic texture (gyri-like ripples).
                        let t = (0.35 * px).sin() * (0.31 * py).sin() * (0.27 * pz).cos();
                        (f32::from(CT_BRAIN) + 6.0 * t) as u8
                    }
                };
                if let Some(p) = v.get_mut(x + n * (y + n * z)) {
                    *p = value;
                }
            }
        }
    }
    v
}

/// A transfer function for [`ct_head`]: air transparent, soft tissue a faint skin tone, the
/// brain faint pink, bone nearly opaque ivory.
pub fn ct_transfer_function() -> Vec<ControlPoint> {
    let p = |s: f32, c: [f32; 3], a: f32| ControlPoint { s, c, a };
    vec![
        p(0.0, [0.0; 3], 0.0),
        p(40.0, [0.9, 0.6, 0.5], 0.0),
        p(80.0, [0.9, 0.6, 0.5], 0.02),
        p(110.0, [0.9, 0.5, 0.5], 0.03),
        p(160.0, [1.0, 0.95, 0.85], 0.2),
        p(230.0, [1.0, 1.0, 0.95], 0.9),
        p(255.0, [1.0, 1.0, 1.0], 0.95),
    ]
}
