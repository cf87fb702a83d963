//! `Film`: LuxRender 1.x's `fleximage` and the `multiimage` of LuxRender 0.x's exporters
//! (`film/multiimage.cpp`, 2007-8, which tone maps through pbrt-v1's imaging pipeline). Both
//! give the resolution, the display gamma and a tone map; they name the tone map's parameters
//! differently ([`ToneMapNames`]) and the tone maps are the same operators (`reinhard` on
//! absolute luminance for a scene read as LuxRender 0.x, `version.rs`).

use super::params::ParamList;
use super::parser::Parser;
use crate::scene::desc::{FilmDesc, SceneError, ToneMap};

/// How a film type names its tone map and its parameters, and its defaults.
struct ToneMapNames {
    kernel: &'static str,
    default_kernel: &'static str,
    default_burn: f32,
    contrast_ywa: &'static str,
}

/// `film/fleximage.cpp`: `tonemapkernel` (autolinear), `reinhard_burn` 7, `contrast_ywa`.
const FLEXIMAGE: ToneMapNames = ToneMapNames {
    kernel: "tonemapkernel",
    default_kernel: "autolinear",
    default_burn: 7.0,
    contrast_ywa: "contrast_ywa",
};

/// `film/multiimage.cpp` (`MultiImageFilm::CreateFilm`): `tonemapper` (reinhard),
/// `reinhard_burn` 6, `contrast_displayadaptationY`.
const MULTIIMAGE: ToneMapNames = ToneMapNames {
    kernel: "tonemapper",
    default_kernel: "reinhard",
    default_burn: 6.0,
    contrast_ywa: "contrast_displayadaptationY",
};

/// `multiimage`'s parameters that say which files LuxRender writes and when: foton writes the
/// one image of `-o`. Warned once, as a group.
const MULTIIMAGE_OUTPUTS: &[&str] = &[
    "hdr_filename",
    "igi_filename",
    "ldr_filename",
    "hdr_writeinterval",
    "igi_writeinterval",
    "ldr_writeinterval",
    "ldr_displayinterval",
];

impl Parser {
    pub(super) fn film_directive(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        let film = &self.scene.film;
        let x_resolution = self
            .positive_int(params, "xresolution", line)?
            .unwrap_or(film.x_resolution);
        let y_resolution = self
            .positive_int(params, "yresolution", line)?
            .unwrap_or(film.y_resolution);
        let gamma = params.float("gamma")?.unwrap_or(2.2);
        if gamma <= 0.0 {
            return Err(self.error(line, format!("Film: gamma {gamma} must be positive")));
        }
        let names = if kind == "multiimage" {
            self.multiimage_pipeline(line, params)?;
            &MULTIIMAGE
        } else {
            &FLEXIMAGE
        };
        let tonemap = self.tone_map(names, gamma, line, params)?;
        self.scene.film = FilmDesc {
            x_resolution,
            y_resolution,
            gamma,
            filename: params.string("filename")?.map(without_image_extension),
            tonemap,
        };
        Ok(())
    }

    fn tone_map(
        &mut self,
        names: &ToneMapNames,
        gamma: f32,
        line: usize,
        params: &mut ParamList,
    ) -> Result<ToneMap, SceneError> {
        let kernel = params.string(names.kernel)?;
        Ok(match kernel.as_deref().unwrap_or(names.default_kernel) {
            "autolinear" => ToneMap::AutoLinear,
            "linear" => {
                // LuxRender's linear tone map, after the ISO speed definition: a scene luminance
                // of 10 / sensitivity, exposed for `exposure` s at f-number `fstop`, maps to
                // 118/255 on a display of gamma `linear_gamma`:
                // scale = exposure / fstop^2 * sensitivity * 0.65 / 10 * (118/255)^gamma.
                let sensitivity = params.float("linear_sensitivity")?.unwrap_or(100.0);
                let exposure = params.float("linear_exposure")?.unwrap_or(1.0 / 1000.0);
                let fstop = params.float("linear_fstop")?.unwrap_or(2.8);
                let display_gamma = params.float("linear_gamma")?.unwrap_or(gamma);
                let scale = exposure / (fstop * fstop) * sensitivity * 0.65 / 10.0
                    * (118.0f32 / 255.0).powf(display_gamma);
                ToneMap::Linear { scale }
            }
            // `tonemaps/reinhard.cpp`, `contrast.cpp`, `maxwhite.cpp`; LuxRender 0.x's Reinhard
            // for scenes read as that release (`version.rs`).
            "reinhard" => {
                let prescale = params.float("reinhard_prescale")?.unwrap_or(1.0);
                let postscale = params.float("reinhard_postscale")?.unwrap_or(1.0);
                let burn = params.float("reinhard_burn")?.unwrap_or(names.default_burn);
                if self.version.has_absolute_reinhard() {
                    ToneMap::ReinhardAbsolute {
                        prescale,
                        postscale,
                        burn,
                    }
                } else {
                    ToneMap::Reinhard {
                        prescale,
                        postscale,
                        burn,
                    }
                }
            }
            "contrast" => ToneMap::Contrast {
                ywa: params.float(names.contrast_ywa)?.unwrap_or(50.0),
            },
            "maxwhite" => ToneMap::MaxWhite,
            other => {
                self.warn(
                    line,
                    format!(
                        "Film: {} \"{other}\" unsupported: linear, scale 1",
                        names.kernel
                    ),
                );
                ToneMap::Linear { scale: 1.0 }
            }
        })
    }

    /// `multiimage`'s pipeline settings besides the tone map (pbrt-v1's
    /// `ApplyImagingPipeline`): `bloomwidth` and `bloomradius` (0: no bloom) and `dither` (0:
    /// none) are read, and warned as not applied when they would change the image; the output
    /// settings are warned once together.
    fn multiimage_pipeline(
        &mut self,
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        for name in ["bloomwidth", "bloomradius", "dither"] {
            if let Some(value) = params.float(name)?
                && value != 0.0
            {
                self.warn(
                    line,
                    format!("Film \"multiimage\": \"{name}\" {value} not applied"),
                );
            }
        }
        let mut outputs = Vec::new();
        for name in MULTIIMAGE_OUTPUTS {
            if params.ignore(name) {
                outputs.push(*name);
            }
        }
        if !outputs.is_empty() {
            self.warn(
                line,
                format!(
                    "Film \"multiimage\": output files and intervals ignored (foton writes the \
                     image of -o): {}",
                    outputs.join(", ")
                ),
            );
        }
        Ok(())
    }
}

/// The film's output name without an image extension (LuxBlend writes none, but names like
/// `cornell-box.Scene.00244` contain dots, so only known extensions are removed).
fn without_image_extension(filename: String) -> String {
    const EXTENSIONS: &[&str] = &[".png", ".exr", ".tga", ".jpg", ".jpeg", ".flm"];
    EXTENSIONS
        .iter()
        .find_map(|ext| {
            let stem_len = filename.len().checked_sub(ext.len())?;
            let (stem, tail) = filename.split_at_checked(stem_len)?;
            tail.eq_ignore_ascii_case(ext).then(|| stem.to_string())
        })
        .unwrap_or(filename)
}
