//! The LuxRender release a scene was written for, and what foton renders differently for
//! releases before 1.0.
//!
//! LuxBlend starts every scene with a comment naming the release it exported for
//! (`# Lux Render v0.6RC6 Scene File`, `# LuxRender v0.8 Scene File`); `-D lux_version=X.Y`
//! overrides it, and a file without one is read as LuxRender 1.x final. Two things LuxRender
//! changed show in a rendered image (`docs/luxrender-scenes.md`, "LuxRender versions"):
//!
//! - **The Reinhard tone map.** Up to 0.x (`tonemaps/reinhard.cpp` of LuxRender/Lux before the
//!   `luxrays` colour classes) it adapts to the arithmetic mean luminance and applies the curve
//!   to the *absolute* luminance; 1.x's adapts to the log-average and is scale invariant. The
//!   earlier one is [`crate::film::ToneMap::ReinhardAbsolute`].
//! - **Absolute luminance then matters**, so foton renders in LuxRender's film units for such
//!   scenes: LuxRender's film holds photometric luminance, 683 lm/W times the integral of the
//!   spectrum against the CIE y function (the XYZ weights `spd_ciey` are CIE_Y x 683 x
//!   (720 - 380) / WAVELENGTH_SAMPLES, `core/spectrumwavelengths.cpp`), where foton's radiance
//!   unit is a spectrum whose y-weighted mean is 1. A light with only `gain` is thus
//!   [`photometric_scale`] times brighter in LuxRender's film than in foton's; a light normalised
//!   by `power` x `efficacy` is not, because LuxRender divides by the texture's photometric
//!   `Y()` (`SPD::Y()`: 683 x sum of S ȳ, `core/spd.cpp`; `textures/blackbody.h`,
//!   `textures/constant.h`), giving luminance power x efficacy / (pi area) as foton does.

use crate::texture::blackbody::cie_xyz;

/// A LuxRender release, major.minor (a release candidate counts as its release).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct LuxVersion {
    pub major: u32,
    pub minor: u32,
}

/// What foton reads a file without a version comment as: LuxRender 1.x final (1.6).
pub const FINAL: LuxVersion = LuxVersion { major: 1, minor: 6 };

/// The first release read with 1.x's Reinhard. The references rendered with the earlier one
/// (TestSuite's `bumpmapping`, `bidir-simple`) were exported for 0.6 and carry Film parameters
/// of 0.7 to 0.9 (`ldr_clamp_method`, `write_png_gamutclamp`); the release between 0.9 and 1.6
/// that changed the operator was not pinned down, so 1.0 is the boundary.
const LOG_AVERAGE_REINHARD: LuxVersion = LuxVersion { major: 1, minor: 0 };

/// The `-D` scene parameter that overrides the file's version comment.
pub const OVERRIDE_PARAMETER: &str = "lux_version";

impl LuxVersion {
    /// Reads `0.6`, `v0.6RC6`, `1.6.1`, `0.8`: the first two numbers; `None` for anything else.
    pub fn parse(text: &str) -> Option<Self> {
        let text = text.trim();
        let text = text.strip_prefix(['v', 'V']).unwrap_or(text);
        let mut parts = text.splitn(2, '.');
        let major = parts.next()?.parse().ok()?;
        let minor_digits: String = parts
            .next()?
            .chars()
            .take_while(char::is_ascii_digit)
            .collect();
        let minor = minor_digits.parse().ok()?;
        Some(Self { major, minor })
    }

    /// The version in the exporter's comment at the top of a scene file, before its first
    /// directive: `# Lux Render v0.6RC6 Scene File`, `# LuxRender v0.8 Scene File`.
    pub fn from_header(text: &str) -> Option<Self> {
        text.lines()
            .map(str::trim)
            .take_while(|line| line.is_empty() || line.starts_with('#'))
            .find_map(|line| {
                let words: Vec<&str> = line.trim_start_matches('#').split_whitespace().collect();
                let after_name = match words.as_slice() {
                    ["Lux", "Render", version, ..] | ["LuxRender", version, ..] => version,
                    _ => return None,
                };
                Self::parse(after_name)
            })
    }

    /// Whether this release's Reinhard is the earlier one, on absolute luminance in LuxRender's
    /// film units (see the module's documentation).
    pub fn has_absolute_reinhard(self) -> bool {
        self < LOG_AVERAGE_REINHARD
    }
}

impl std::fmt::Display for LuxVersion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}.{}", self.major, self.minor)
    }
}

/// How much brighter LuxRender's film shows a light with only `gain` than foton's radiance:
/// 683 lm/W x the integral of the CIE y function over LuxRender's 380-720 nm (about 106.9 nm),
/// which is about 73,000.
pub fn photometric_scale() -> f32 {
    const LAMBDA_MIN: f32 = 380.0;
    const LAMBDA_MAX: f32 = 720.0;
    const STEPS: usize = 340;
    let step = (LAMBDA_MAX - LAMBDA_MIN) / STEPS as f32;
    let y_integral: f32 = (0..STEPS)
        .map(|i| cie_xyz(LAMBDA_MIN + (i as f32 + 0.5) * step).y * step)
        .sum();
    683.0 * y_integral
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_exporters_comments() {
        let v = |major, minor| Some(LuxVersion { major, minor });
        // The shared scenes' and LuxBlend's comments; then no comment, a comment naming no
        // version, and a version comment after the first directive.
        for (text, expected) in [
            (
                "# Lux Render v0.6RC6 Scene File\n# Exported by LuxBlend\n",
                v(0, 6),
            ),
            (
                "\n# LuxRender v0.8 Scene File\nLookAt 0 0 0 0 0 1 0 1 0",
                v(0, 8),
            ),
            ("# LuxRender v1.6 Scene File", v(1, 6)),
            ("# Lux Render v0.1 Scene File", v(0, 1)),
            ("LookAt 0 0 0 0 0 1 0 1 0", None),
            ("#Translate 0 0 35\nLookAt", None),
            (
                "LookAt 0 0 0 0 0 1 0 1 0\n# LuxRender v0.8 Scene File",
                None,
            ),
        ] {
            assert_eq!(LuxVersion::from_header(text), expected, "{text}");
        }
        assert_eq!(LuxVersion::parse("1.6.1"), v(1, 6));
        assert_eq!(LuxVersion::parse("0.9dev"), v(0, 9));
        assert_eq!(LuxVersion::parse("six"), None);
        assert_eq!(LuxVersion::parse("1"), None);
    }

    #[test]
    fn releases_before_one_have_the_absolute_reinhard() {
        assert!(LuxVersion { major: 0, minor: 6 }.has_absolute_reinhard());
        assert!(LuxVersion { major: 0, minor: 9 }.has_absolute_reinhard());
        assert!(!LuxVersion { major: 1, minor: 0 }.has_absolute_reinhard());
        assert!(!FINAL.has_absolute_reinhard());
    }

    /// The CIE 1931 y function integrates to 106.857 nm over 360-830 nm (the tabulated
    /// function, as pbrt-v4's `CIE_Y_integral`); 380-720 nm holds all but about 0.1% of it, and
    /// foton's analytic fit of the functions is within about 1%.
    #[test]
    fn photometric_scale_is_683_times_the_y_integral() {
        let expected = 683.0 * 106.857;
        let scale = photometric_scale();
        assert!((scale / expected - 1.0).abs() < 0.01, "{scale} {expected}");
    }
}
