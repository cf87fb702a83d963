//! `Material "glossytranslucent"` (LuxRender 1.x `materials/glossytranslucent.cpp`): `Kd` and
//! `Kt` 1; the front coating `Ks` 1 (times ((n - 1) / (n + 1))^2 for `index` n > 0), `Ka` 0,
//! `d` 0, `uroughness` = `vroughness` = 0.1 (each clamped to [6e-3, 1], Schlick's r = u v),
//! `multibounce` false. With `onesided` (true) the back coating is the front's; otherwise it
//! is read from `backface_Ks`, `backface_index`, `backface_Ka`, `backface_d`,
//! `backface_uroughness`, `backface_vroughness`, `backface_multibounce`, whose defaults are 0
//! and false (a rough, black back coating unless given). Each coating's Schlick anisotropy
//! comes from its clamped u and v (`glossytranslucent.cpp`: `anisotropy`, `banisotropy`).

use glam::Vec3;

use super::materials::schlick_anisotropy;
use super::params::ParamList;
use super::parser::Parser;
use crate::bsdf::coated_glossy::coating_f0;
use crate::scene::desc::{ColorParam, GlossyCoatingDesc, MaterialDesc, SceneError};

/// The coating's parameter names: the front's, or the back's with `backface_` before them.
struct CoatingNames {
    prefix: &'static str,
    /// Defaults of Ks and of both roughnesses.
    ks: f32,
    roughness: f32,
}

impl Parser {
    pub(super) fn glossy_translucent(
        &mut self,
        line: usize,
        params: &mut ParamList,
    ) -> Result<MaterialDesc, SceneError> {
        let diffuse = self.color_param(params, "Kd", Vec3::ONE, line)?;
        let transmittance = self.color_param(params, "Kt", Vec3::ONE, line)?;
        let front_names = CoatingNames {
            prefix: "",
            ks: 1.0,
            roughness: 0.1,
        };
        let front = self.glossy_coating(&front_names, line, params)?;
        let back = if params.bool("onesided")?.unwrap_or(true) {
            front.clone()
        } else {
            let back_names = CoatingNames {
                prefix: "backface_",
                ks: 0.0,
                roughness: 0.0,
            };
            self.glossy_coating(&back_names, line, params)?
        };
        Ok(MaterialDesc::GlossyTranslucent {
            diffuse,
            transmittance,
            front,
            back,
        })
    }

    fn glossy_coating(
        &mut self,
        names: &CoatingNames,
        line: usize,
        params: &mut ParamList,
    ) -> Result<GlossyCoatingDesc, SceneError> {
        let name = |base: &str| format!("{}{base}", names.prefix);
        let index = self.constant_float(params, &name("index"), 0.0, line)?;
        let specular = match self.color_param(params, &name("Ks"), Vec3::splat(names.ks), line)? {
            ColorParam::Constant(ks) => ColorParam::Constant(coating_f0(ks, index)),
            texture => texture,
        };
        let absorption = self.color_param(params, &name("Ka"), Vec3::ZERO, line)?;
        let depth = self.constant_float(params, &name("d"), 0.0, line)?;
        let clamp = |r: f32| r.clamp(6e-3, 1.0);
        let u = self.constant_float(params, &name("uroughness"), names.roughness, line)?;
        let v = self.constant_float(params, &name("vroughness"), names.roughness, line)?;
        Ok(GlossyCoatingDesc {
            specular,
            absorption,
            depth,
            roughness: clamp(u) * clamp(v),
            anisotropy: schlick_anisotropy(clamp(u), clamp(v)),
            multibounce: params.bool(&name("multibounce"))?.unwrap_or(false),
        })
    }
}
