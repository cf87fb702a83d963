//! LuxRender's `carpaint` presets: the measured paints of Günther et al. 2005 ("Efficient
//! Acquisition and Realistic Rendering of Car Paint") as LuxRender 1.x tabulates them
//! (`materials/carpaint.h`, `carpaintdata`; the same values in LuxCore's `carpaint.cpp`).

use glam::Vec3;

/// One paint: the diffuse base `kd`, the three lobes' colours `ks`, Fresnel reflectances `r`
/// at normal incidence and roughnesses `m`.
pub struct CarPaintPreset {
    pub name: &'static str,
    pub kd: Vec3,
    pub ks: [Vec3; 3],
    pub r: [f32; 3],
    pub m: [f32; 3],
}

const fn paint(
    name: &'static str,
    kd: [f32; 3],
    ks: [[f32; 3]; 3],
    r: [f32; 3],
    m: [f32; 3],
) -> CarPaintPreset {
    CarPaintPreset {
        name,
        kd: Vec3::from_array(kd),
        ks: [
            Vec3::from_array(ks[0]),
            Vec3::from_array(ks[1]),
            Vec3::from_array(ks[2]),
        ],
        r,
        m,
    }
}

/// The presets, the first ("ford f8") also LuxRender's default for each missing parameter.
pub const PRESETS: [CarPaintPreset; 8] = [
    paint(
        "ford f8",
        [0.0012, 0.0015, 0.0018],
        [
            [0.0049, 0.0076, 0.0120],
            [0.0100, 0.0130, 0.0180],
            [0.0070, 0.0065, 0.0077],
        ],
        [0.1500, 0.0870, 0.9000],
        [0.3200, 0.1100, 0.0130],
    ),
    paint(
        "polaris silber",
        [0.0550, 0.0630, 0.0710],
        [
            [0.0650, 0.0820, 0.0880],
            [0.1100, 0.1100, 0.1300],
            [0.0080, 0.0130, 0.0150],
        ],
        [1.0000, 0.9200, 0.9000],
        [0.3800, 0.1700, 0.0130],
    ),
    paint(
        "opel titan",
        [0.0110, 0.0130, 0.0150],
        [
            [0.0570, 0.0660, 0.0780],
            [0.1100, 0.1200, 0.1300],
            [0.0095, 0.0140, 0.0160],
        ],
        [0.8500, 0.8600, 0.9000],
        [0.3800, 0.1700, 0.0140],
    ),
    paint(
        "bmw339",
        [0.0120, 0.0150, 0.0160],
        [
            [0.0620, 0.0760, 0.0800],
            [0.1100, 0.1200, 0.1200],
            [0.0083, 0.0150, 0.0160],
        ],
        [0.9200, 0.8700, 0.9000],
        [0.3900, 0.1700, 0.0130],
    ),
    paint(
        "2k acrylack",
        [0.4200, 0.3200, 0.1000],
        [
            [0.0000, 0.0000, 0.0000],
            [0.0280, 0.0260, 0.0060],
            [0.0170, 0.0075, 0.0041],
        ],
        [1.0000, 0.9000, 0.1700],
        [0.8800, 0.8000, 0.0150],
    ),
    paint(
        "white",
        [0.6100, 0.6300, 0.5500],
        [
            [2.6e-06, 0.00031, 3.1e-08],
            [0.0130, 0.0110, 0.0083],
            [0.0490, 0.0420, 0.0370],
        ],
        [0.0490, 0.4500, 0.1700],
        [1.0000, 0.1500, 0.0150],
    ),
    paint(
        "blue",
        [0.0079, 0.0230, 0.1000],
        [
            [0.0011, 0.0015, 0.0019],
            [0.0250, 0.0300, 0.0430],
            [0.0590, 0.0740, 0.0820],
        ],
        [1.0000, 0.0940, 0.1700],
        [0.1500, 0.0430, 0.0200],
    ),
    paint(
        "blue matte",
        [0.0099, 0.0360, 0.1200],
        [
            [0.0032, 0.0045, 0.0059],
            [0.1800, 0.2300, 0.2800],
            [0.0400, 0.0490, 0.0510],
        ],
        [1.0000, 0.0460, 0.1700],
        [0.1600, 0.0750, 0.0340],
    ),
];

/// The preset called `name`, if any.
pub fn preset(name: &str) -> Option<&'static CarPaintPreset> {
    PRESETS.iter().find(|p| p.name == name)
}
