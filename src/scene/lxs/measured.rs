//! LuxRender 0.x's measured materials (`materials/primer.cpp`, `felt.cpp`, `clay.cpp`,
//! `bluepaint.cpp`, `skin.cpp` of LuxRender/Lux, inherited from pbrt-v1): each a fixed
//! Lafortune fit (diffuse albedo and three lobes, red, green, blue), with no parameter but the
//! `bumpmap` every material takes. The coefficients keep the sources' digits, some beyond
//! f32's precision.
#![allow(clippy::excessive_precision)]

use glam::Vec3;

use crate::bsdf::lafortune::{LafortuneFit, LafortuneLobe};

const fn rgb(r: f32, g: f32, b: f32) -> Vec3 {
    Vec3::new(r, g, b)
}

const fn lobe(xy: Vec3, z: Vec3, exponent: Vec3) -> LafortuneLobe {
    LafortuneLobe { xy, z, exponent }
}

const PRIMER: LafortuneFit = LafortuneFit {
    diffuse: rgb(0.118230, 0.121218, 0.133209),
    lobes: [
        lobe(
            rgb(-0.399286, -1.033473, -1.058104),
            rgb(0.167504, 0.009545, -0.068002),
            rgb(2.466633, 7.637253, 8.117645),
        ),
        lobe(
            rgb(-1.041861, -1.100108, -1.087779),
            rgb(0.014375, -0.198147, -0.053605),
            rgb(7.993722, 29.446268, 41.988990),
        ),
        lobe(
            rgb(-1.098605, -0.379883, -0.449038),
            rgb(-0.145110, 0.159127, 0.173224),
            rgb(31.899719, 2.372852, 2.636161),
        ),
    ],
};

const FELT: LafortuneFit = LafortuneFit {
    diffuse: rgb(0.025865, 0.025865, 0.025865),
    lobes: [
        lobe(
            rgb(-0.304075, -0.304075, -0.304075),
            rgb(-0.065992, -0.065992, -0.065992),
            rgb(3.047892, 3.047892, 3.047892),
        ),
        lobe(
            rgb(-0.749561, -0.749561, -0.749561),
            rgb(-1.167929, -1.167929, -1.167929),
            rgb(6.931827, 6.931827, 6.931827),
        ),
        lobe(
            rgb(1.004921, 1.004921, 1.004921),
            rgb(-0.205529, -0.205529, -0.205529),
            rgb(94.117332, 94.117332, 94.117332),
        ),
    ],
};

const CLAY: LafortuneFit = LafortuneFit {
    diffuse: rgb(0.383626, 0.260749, 0.274207),
    lobes: [
        lobe(
            rgb(-1.089701, -1.102701, -1.107603),
            rgb(-1.354682, -2.714801, -1.569866),
            rgb(17.968505, 11.024489, 21.270282),
        ),
        lobe(
            rgb(-0.733381, -0.793320, -0.848206),
            rgb(0.676108, 0.679314, 0.726031),
            rgb(8.219745, 9.055139, 11.261951),
        ),
        lobe(
            rgb(-1.010548, -1.012378, -1.011263),
            rgb(0.910783, 0.885239, 0.892451),
            rgb(152.912795, 141.937171, 201.046802),
        ),
    ],
};

const BLUE_PAINT: LafortuneFit = LafortuneFit {
    diffuse: rgb(0.3094, 0.39667, 0.70837),
    lobes: [
        lobe(
            rgb(0.870567, 0.857255, 0.670982),
            rgb(0.803624, 0.774290, 0.586674),
            rgb(21.820103, 18.597755, 7.472717),
        ),
        lobe(
            rgb(-0.451218, -0.406681, -0.477976),
            rgb(0.023123, 0.017625, 0.227295),
            rgb(2.774499, 2.581499, 3.677653),
        ),
        lobe(
            rgb(-1.031545, -1.029426, -1.026588),
            rgb(0.706734, 0.696530, 0.687715),
            rgb(66.899060, 63.767912, 57.489181),
        ),
    ],
};

const SKIN: LafortuneFit = LafortuneFit {
    diffuse: rgb(0.428425, 0.301341, 0.331054),
    lobes: [
        lobe(
            rgb(-1.131747, -1.016939, -0.966018),
            rgb(-1.209182, -1.462488, -1.222419),
            rgb(6.421658, 3.699932, 3.524889),
        ),
        lobe(
            rgb(-0.546570, -0.643533, -0.638934),
            rgb(0.380123, 0.410559, 0.437367),
            rgb(3.685044, 4.266495, 4.539742),
        ),
        lobe(
            rgb(-0.998888, -1.020153, -1.027479),
            rgb(0.857998, 0.703913, 0.573625),
            rgb(64.208486, 63.919687, 43.809866),
        ),
    ],
};

/// The measured material of a LuxRender material type, if it is one.
pub fn measured_material(kind: &str) -> Option<&'static LafortuneFit> {
    match kind {
        "primer" => Some(&PRIMER),
        "felt" => Some(&FELT),
        "clay" => Some(&CLAY),
        "bluepaint" => Some(&BLUE_PAINT),
        "skin" => Some(&SKIN),
        _ => None,
    }
}
