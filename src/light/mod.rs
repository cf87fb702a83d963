//! Lights: point, spot and distant lights, sun discs and the environment are entities of their
//! own; area lights are shapes with an `AreaEmitter`. At startup [`build_light_table`] gathers
//! them into the [`LightTable`] the shade stage samples, choosing one light for next-event
//! estimation by the [`LightSelection`].

pub mod area;
pub mod bvh;
pub mod distant;
pub mod infinite;
pub mod point;
pub mod spot;
pub mod sun_disc;

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

use crate::sampling::{AliasTable, ONE_MINUS_EPSILON};
use crate::shape::geometry::SceneGeometry;
use crate::shared::Shared;
use area::AreaLight;
use bvh::{LightBounds, LightBvh};
use distant::DistantLight;
use infinite::{Environment, InfiniteLight};
use point::PointLight;
use spot::SpotLight;
use sun_disc::SunDiscLight;

/// Light arriving at a point from one sampled direction.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the point towards the light.
    pub wi: Vec3,
    /// Distance to the light point (infinite for distant and environment lights).
    pub distance: f32,
    pub radiance: Vec3,
    /// Solid-angle density; 1 for delta lights.
    pub pdf: f32,
    /// A point or directional light: no MIS, BSDF sampling can never hit it.
    pub delta: bool,
}

#[derive(Clone, Debug)]
pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
    Distant(DistantLight),
    SunDisc(SunDiscLight),
    Environment(Environment),
    Area(AreaLight),
}

impl Light {
    #[inline]
    pub fn sample(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        match self {
            Light::Point(light) => light.sample(p),
            Light::Spot(light) => light.sample(p),
            Light::Distant(light) => Some(light.sample()),
            Light::SunDisc(light) => Some(light.sample(u)),
            Light::Environment(light) => light.sample(u),
            Light::Area(light) => light.sample(p, u),
        }
    }

    /// A light of one position or one direction (pbrt-v4's `IsDeltaLight`): its `sample`
    /// ignores `u`.
    pub fn is_delta(&self) -> bool {
        matches!(self, Light::Point(_) | Light::Spot(_) | Light::Distant(_))
    }

    /// `sample` for next-event estimation that MIS combines with BSDF sampling: the
    /// environment then samples its compensated distribution ([`Environment::sample_for_mis`]).
    #[inline]
    pub fn sample_for_mis(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        match self {
            Light::Environment(light) => light.sample_for_mis(u),
            _ => self.sample(p, u),
        }
    }

    /// Whether `sample_for_mis` can return a sample: not for a constant sky, which BSDF
    /// sampling alone covers (the path tracer never picks it for next-event estimation).
    pub fn is_sampled_for_mis(&self) -> bool {
        match self {
            Light::Environment(light) => !light.is_constant(),
            _ => true,
        }
    }

    /// Where the light is, which way it shines and its power, for the light BVH; `None` for
    /// the lights at infinity (distant lights, sun discs, the environment).
    pub fn bounds(&self) -> Option<LightBounds> {
        match self {
            Light::Point(light) => Some(LightBounds::point(light.position, light.power())),
            Light::Spot(light) => Some(light.bounds()),
            Light::Area(light) => Some(light.bounds()),
            Light::Distant(_) | Light::SunDisc(_) | Light::Environment(_) => None,
        }
    }
}

/// How next-event estimation picks the one light it samples at a vertex.
///
/// In proportion to power, a bright sky starves a small lamp that lights most of what the
/// camera sees (its power counts light that passes the scene by); uniformly, a dim light gets
/// as many samples as the sun. The mix, half of each (a defensive mixture, Hesterberg 1995),
/// keeps every light's probability at least 1 / 2n and at least half its power share, so
/// neither case can be worse than twice the better strategy's variance. Of the three, uniform
/// had the least error on the scenes measured (docs/error-per-second.md), as in Mitsuba 3. The
/// light BVH ([`bvh`]), the default (as in pbrt-v4), chooses by each light's estimated
/// contribution at the shading point: the lights at infinity uniformly, the rest through the
/// tree. With one light to choose from, every selection is the same.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSelection {
    Power,
    Uniform,
    Mixed,
    #[default]
    Bvh,
}

impl LightSelection {
    /// Selection weights from the lights' powers.
    pub fn weights(self, power: &[f32]) -> Vec<f32> {
        let n = power.len() as f32;
        let clean = |p: f32| if p.is_finite() && p > 0.0 { p } else { 0.0 };
        let total: f32 = power.iter().map(|&p| clean(p)).sum();
        match self {
            // The light BVH's table serves only where there is no choice to make.
            Self::Uniform | Self::Bvh => vec![1.0; power.len()],
            Self::Power => power.iter().map(|&p| clean(p)).collect(),
            Self::Mixed if total > 0.0 => power
                .iter()
                .map(|&p| 0.5 * clean(p) / total + 0.5 / n)
                .collect(),
            Self::Mixed => vec![1.0; power.len()],
        }
    }
}

#[derive(Resource, Clone, Debug)]
pub struct LightTable {
    pub lights: Vec<Light>,
    /// Over `selectable`: the lights next-event estimation under MIS can sample.
    selection: AliasTable,
    /// Indices into `lights` of the selectable lights, in the selection table's order.
    selectable: Vec<u32>,
    /// Each light's selection probability (0 for one never selected); NaN for a light whose
    /// probability depends on the point, one in the light BVH ([`ChoiceByPosition`]).
    probability: Vec<f32>,
    /// The choice where there is no choice: `None` without selectable lights, the one light
    /// and its probability with one (the table's answer for every `u`).
    sole_choice: Option<(usize, f32)>,
    /// With [`LightSelection::Bvh`] and two or more selectable lights: the choice by position,
    /// in place of the table.
    by_position: Option<ChoiceByPosition>,
    /// Light index of each of the geometry's emissive shapes.
    emitter_light: Vec<u32>,
    environment: Option<u32>,
    /// Indices into `lights` of the sun discs, which escaped rays can see.
    sun_discs: Vec<u32>,
    /// See [`LightTable::escaped_light`].
    escaped_light: EscapedLight,
}

/// What the rays that leave the scene see.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EscapedLight {
    /// Nothing: no environment and no sun disc.
    Dark,
    /// The same radiance from every direction, with MIS weight 1: a constant sky, which light
    /// sampling leaves to BSDF sampling ([`Light::sample_for_mis`]), so that no other strategy
    /// finds it; no sun disc.
    Uniform(Vec3),
    /// An environment map, with sun discs or without.
    Map,
    /// Sun discs, under a constant sky or none.
    SunDiscs,
}

impl EscapedLight {
    fn of(lights: &[Light], environment: Option<u32>, sun_discs: &[u32]) -> Self {
        let radiance = match environment.and_then(|index| lights.get(index as usize)) {
            Some(Light::Environment(environment)) => match environment.constant_radiance() {
                Some(radiance) => radiance,
                None => return Self::Map,
            },
            _ => Vec3::ZERO,
        };
        match (sun_discs.is_empty(), radiance == Vec3::ZERO) {
            (false, _) => Self::SunDiscs,
            (true, true) => Self::Dark,
            (true, false) => Self::Uniform(radiance),
        }
    }
}

impl LightTable {
    /// From all the lights and their powers: the selection weights are computed over the lights
    /// that next-event estimation samples (a constant sky is not one: [`Light::sample_for_mis`]),
    /// so the others' share goes to them; their probabilities sum to 1, the rest have 0.
    fn new(
        lights: Vec<Light>,
        power: &[f32],
        selection_kind: LightSelection,
        emitter_light: Vec<u32>,
        environment: Option<u32>,
    ) -> Self {
        let sun_discs: Vec<u32> = (0..lights.len() as u32)
            .filter(|&i| matches!(lights[i as usize], Light::SunDisc(_)))
            .collect();
        let selectable: Vec<u32> = (0..lights.len() as u32)
            .filter(|&i| lights[i as usize].is_sampled_for_mis())
            .collect();
        let selectable_power: Vec<f32> = selectable.iter().map(|&i| power[i as usize]).collect();
        let selection = AliasTable::new(&selection_kind.weights(&selectable_power));
        let mut probability = vec![0.0; lights.len()];
        for (k, &i) in selectable.iter().enumerate() {
            probability[i as usize] = selection.pdf(k);
        }
        let sole_choice = match selectable.as_slice() {
            [only] => Some((*only as usize, selection.sample(0.0).1)),
            _ => None,
        };
        let by_position = (selection_kind == LightSelection::Bvh && selectable.len() > 1)
            .then(|| ChoiceByPosition::new(&lights, &selectable));
        if let Some(by_position) = &by_position {
            for &i in &selectable {
                probability[i as usize] = by_position.probability_at_infinity(i);
            }
        }
        let escaped_light = EscapedLight::of(&lights, environment, &sun_discs);
        Self {
            lights,
            selection,
            selectable,
            probability,
            sole_choice,
            by_position,
            emitter_light,
            environment,
            sun_discs,
            escaped_light,
        }
    }

    /// What an escaped ray sees: with none or one radiance for every direction, its shading
    /// is a multiply-add at most.
    #[inline(always)]
    pub fn escaped_light(&self) -> EscapedLight {
        self.escaped_light
    }

    /// Picks the light for next-event estimation at the point `p`: by the table's selection
    /// weights in O(1), or with the light BVH by position; (index, probability), `None` when no
    /// light can be sampled that way. Inlined, the rest out of line: most scenes have one
    /// selectable light (a lamp under a constant sky), whose choice is a copy (27 to about 5
    /// instructions a vertex on the Cornell box).
    #[inline(always)]
    pub fn choose(&self, u: f32, p: Vec3) -> Option<(usize, f32)> {
        if !self.has_choice() {
            return self.sole_choice;
        }
        self.choose_among(u, p)
    }

    /// Whether [`LightTable::choose`] reads its `u`: there are two or more lights to choose
    /// from (a caller may then skip drawing it).
    #[inline(always)]
    pub fn has_choice(&self) -> bool {
        self.selectable.len() > 1
    }

    /// Whether [`LightTable::choose`] can pick a light: there is one to sample.
    pub fn can_choose(&self) -> bool {
        !self.selectable.is_empty()
    }

    #[inline(never)]
    fn choose_among(&self, u: f32, p: Vec3) -> Option<(usize, f32)> {
        if let Some(by_position) = &self.by_position {
            return by_position.choose(u, p);
        }
        let (k, probability, _) = self.selection.sample(u);
        Some((self.selectable[k] as usize, probability))
    }

    /// The probability that [`LightTable::choose`] at `p` picks light `index`. Inlined, the
    /// light BVH's walk out of line: where there is no choice to make (most scenes) it is a
    /// table's entry.
    #[inline(always)]
    pub fn selection_probability(&self, index: usize, p: &Vec3) -> f32 {
        let probability = self.probability.get(index).copied().unwrap_or(0.0);
        if probability.is_nan() {
            self.probability_in_tree(index, *p)
        } else {
            probability
        }
    }

    #[inline(never)]
    fn probability_in_tree(&self, index: usize, p: Vec3) -> f32 {
        self.by_position
            .as_ref()
            .map_or(0.0, |by_position| by_position.probability(index, p))
    }

    /// The area light of emissive shape `emitter`, with its index.
    pub fn area_light(&self, emitter: u32) -> Option<(usize, &AreaLight)> {
        let index = *self.emitter_light.get(emitter as usize)? as usize;
        match self.lights.get(index) {
            Some(Light::Area(light)) => Some((index, light)),
            _ => None,
        }
    }

    pub fn environment(&self) -> Option<(usize, &Environment)> {
        let index = self.environment? as usize;
        match self.lights.get(index) {
            Some(Light::Environment(light)) => Some((index, light)),
            _ => None,
        }
    }

    /// The sun discs with their indices: what an escaped ray sees besides the environment.
    pub fn sun_discs(&self) -> impl Iterator<Item = (usize, &SunDiscLight)> {
        self.sun_discs
            .iter()
            .filter_map(|&i| match &self.lights[i as usize] {
                Light::SunDisc(light) => Some((i as usize, light)),
                _ => None,
            })
    }

    /// The kinds of light, counted, e.g. "2 point, 1 area".
    pub fn kinds(&self) -> String {
        let mut counts: Vec<(&str, usize)> = Vec::new();
        for light in &self.lights {
            let kind = match light {
                Light::Point(_) => "point",
                Light::Spot(_) => "spot",
                Light::Distant(_) => "distant",
                Light::SunDisc(_) => "sun disc",
                Light::Environment(_) => "infinite",
                Light::Area(_) => "area",
            };
            match counts.iter_mut().find(|(k, _)| *k == kind) {
                Some((_, n)) => *n += 1,
                None => counts.push((kind, 1)),
            }
        }
        let parts: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
        parts.join(", ")
    }

    /// Whether any light can be hit by a BSDF-sampled ray (then MIS weights are needed).
    pub fn has_hittable_lights(&self) -> bool {
        self.environment.is_some() || !self.emitter_light.is_empty() || !self.sun_discs.is_empty()
    }
}

/// [`LightSelection::Bvh`]'s choice (pbrt-v4's `BVHLightSampler`): each light at infinity with
/// probability 1 / (n + 1) for n of them, the light BVH with the rest.
#[derive(Clone, Debug)]
struct ChoiceByPosition {
    /// The selectable lights at infinity, by light index.
    infinite: Vec<u32>,
    /// The probability of choosing among `infinite`: n / (n + 1), or without a tree 1 (0
    /// without lights at infinity either: no light to choose).
    infinite_share: f32,
    /// Over the selectable bounded lights, by light index.
    tree: Option<LightBvh>,
}

impl ChoiceByPosition {
    fn new(lights: &[Light], selectable: &[u32]) -> Self {
        let mut bounds = vec![LightBounds::point(Vec3::ZERO, 0.0); lights.len()];
        let mut infinite = Vec::new();
        for &i in selectable {
            match lights[i as usize].bounds() {
                Some(b) => bounds[i as usize] = b,
                None => infinite.push(i),
            }
        }
        let tree = LightBvh::new(&bounds);
        let n = infinite.len() as f32;
        Self {
            infinite_share: match (&tree, infinite.is_empty()) {
                (Some(_), _) => n / (n + 1.0),
                (None, false) => 1.0,
                (None, true) => 0.0,
            },
            infinite,
            tree,
        }
    }

    fn choose(&self, u: f32, p: Vec3) -> Option<(usize, f32)> {
        let share = self.infinite_share;
        if u < share {
            let n = self.infinite.len();
            let k = ((u / share * n as f32) as usize).min(n - 1);
            return Some((self.infinite[k] as usize, share / n as f32));
        }
        let tree = self.tree.as_ref()?;
        let u = ((u - share) / (1.0 - share)).min(ONE_MINUS_EPSILON);
        let (light, probability) = tree.sample(p, u)?;
        Some((light as usize, probability * (1.0 - share)))
    }

    /// The probability of choosing the light at infinity `index` (the same at every point),
    /// or NaN for any other light: its probability depends on the point ([`Self::probability`]).
    fn probability_at_infinity(&self, index: u32) -> f32 {
        if self.infinite.contains(&index) {
            self.infinite_share / self.infinite.len() as f32
        } else {
            f32::NAN
        }
    }

    /// The probability of choosing the bounded light `index` at `p`.
    fn probability(&self, index: usize, p: Vec3) -> f32 {
        self.tree.as_ref().map_or(0.0, |tree| {
            tree.probability(index, p) * (1.0 - self.infinite_share)
        })
    }
}

/// Startup system: the light table from the light entities and the emissive shapes.
pub fn build_light_table(
    selection: Res<crate::settings::Techniques>,
    points: Query<&PointLight>,
    spots: Query<&SpotLight>,
    directional: Query<AnyOf<(&DistantLight, &SunDiscLight)>>,
    environments: Query<&InfiniteLight>,
    geometry: Res<Shared<SceneGeometry>>,
    mut commands: Commands,
) {
    let radius = geometry.bounds_radius;
    let mut lights = Vec::new();
    let mut power = Vec::new();
    for light in &points {
        power.push(light.power());
        lights.push(Light::Point(*light));
    }
    for light in &spots {
        power.push(light.power());
        lights.push(Light::Spot(*light));
    }
    for (distant, sun_disc) in &directional {
        if let Some(light) = distant {
            power.push(light.power(radius));
            lights.push(Light::Distant(*light));
        }
        if let Some(light) = sun_disc {
            power.push(light.power(radius));
            lights.push(Light::SunDisc(*light));
        }
    }
    // One environment at most: the builder merges several into the first, with a warning.
    let environment = environments.iter().next().map(|light| {
        let env = Environment::new(light);
        power.push(env.power(radius));
        lights.push(Light::Environment(env));
        (lights.len() - 1) as u32
    });
    let mut emitter_light = Vec::new();
    for shape in &geometry.emissive_shapes {
        match AreaLight::new(shape, &geometry, selection.solid_angle_rectangles) {
            Some(light) => {
                power.push(light.power());
                lights.push(Light::Area(light));
                emitter_light.push((lights.len() - 1) as u32);
            }
            None => emitter_light.push(u32::MAX),
        }
    }
    commands.insert_resource(Shared::new(LightTable::new(
        lights,
        &power,
        selection.light_selection,
        emitter_light,
        environment,
    )));
}

#[cfg(test)]
mod tests {
    use super::*;
    use spot::SpotFalloff;

    /// `is_delta` says which lights' samples do not depend on `u` (the ray caster draws no
    /// random numbers for those): the same sample from two different `u`, and a different one
    /// from a sun disc of finite size.
    #[test]
    fn delta_lights_are_those_whose_samples_ignore_u() {
        let p = Vec3::new(0.1, -0.2, 0.3);
        let lights = [
            Light::Point(PointLight {
                position: Vec3::new(1.0, 2.0, 3.0),
                intensity: Vec3::ONE,
            }),
            Light::Spot(SpotLight::new(
                Vec3::new(0.0, 0.0, 4.0),
                Vec3::NEG_Z,
                Vec3::ONE,
                (60.0, 10.0),
                SpotFalloff::SmoothCosine,
            )),
            Light::Distant(DistantLight {
                direction_to_light: Vec3::Z,
                radiance: Vec3::ONE,
            }),
            Light::SunDisc(SunDiscLight::new(Vec3::Z, Vec3::ONE, 0.2)),
        ];
        for light in &lights {
            let a = light.sample(p, Vec2::new(0.1, 0.7)).expect("a sample");
            let b = light.sample(p, Vec2::new(0.8, 0.3)).expect("a sample");
            assert_eq!(
                light.is_delta(),
                a.wi == b.wi && a.radiance == b.radiance,
                "{light:?}"
            );
        }
    }

    /// With the light BVH and lights of no power (black lamps) alone, no light is chosen and
    /// each has probability 0.
    #[test]
    fn the_light_bvh_chooses_no_light_of_no_power() {
        let dark = |x: f32| {
            Light::Point(PointLight {
                position: Vec3::new(x, 0.0, 1.0),
                intensity: Vec3::ZERO,
            })
        };
        let lights = vec![dark(0.0), dark(1.0)];
        let table = LightTable::new(lights, &[0.0, 0.0], LightSelection::Bvh, vec![], None);
        let p = Vec3::new(0.5, 0.0, 0.0);
        for i in 0..=100 {
            assert_eq!(table.choose(i as f32 / 100.0, p), None);
        }
        assert_eq!(table.selection_probability(0, &p), 0.0);
    }

    /// `choose` is the selection table's answer, to the bit, for every `u`: with no selectable
    /// light (a constant sky alone), one (its shortcut) and three (the table, power-weighted);
    /// the light indices skip the lights that are never chosen.
    #[test]
    fn choose_is_the_selection_tables_choice() {
        let point = |x: f32| {
            Light::Point(PointLight {
                position: Vec3::new(x, 0.0, 1.0),
                intensity: Vec3::ONE,
            })
        };
        let sky = || {
            Light::Environment(Environment::new(&InfiniteLight {
                radiance: Vec3::ONE,
                map: None,
                light_to_world: glam::Mat3::IDENTITY,
            }))
        };
        let tables = [
            (vec![sky()], vec![1.0]),
            (vec![sky(), point(0.0)], vec![5.0, 2.0]),
            (
                vec![point(0.0), sky(), point(1.0), point(2.0)],
                vec![1.0, 9.0, 3.0, 0.5],
            ),
        ];
        for (lights, power) in tables {
            let table = LightTable::new(lights, &power, LightSelection::Power, vec![], None);
            for i in 0..=1000 {
                let u = i as f32 / 1000.0;
                let expected = (!table.selectable.is_empty()).then(|| {
                    let (k, probability, _) = table.selection.sample(u);
                    (table.selectable[k] as usize, probability)
                });
                let bits = |c: Option<(usize, f32)>| c.map(|(i, p)| (i, p.to_bits()));
                assert_eq!(bits(table.choose(u, Vec3::ZERO)), bits(expected), "u = {u}");
            }
        }
    }

    /// `escaped_light` is what the general escaped-ray shading would find: nothing without a
    /// sky (or under a black one), a constant sky's radiance in every direction with a light
    /// sampling density of 0 there (so an MIS weight of 1), and the general case for a map or
    /// a sun disc.
    #[test]
    fn escaped_light_is_what_every_escaped_ray_sees() {
        let sky = |radiance: Vec3, texels: Option<Vec<Vec3>>| {
            Light::Environment(Environment::new(&InfiniteLight {
                radiance,
                map: texels.map(|texels| crate::material::texture::ImageTexture {
                    width: texels.len() as u32,
                    height: 1,
                    texels: std::sync::Arc::new(texels),
                    scale: Vec2::ONE,
                    delta: Vec2::ZERO,
                    wrap: Default::default(),
                }),
                light_to_world: glam::Mat3::IDENTITY,
            }))
        };
        let sun = || Light::SunDisc(SunDiscLight::new(Vec3::Z, Vec3::ONE, 0.01));
        let radiance = Vec3::new(0.5, 1.0, 2.0);
        let escaped = |lights: Vec<Light>| {
            let environment = lights
                .iter()
                .position(|light| matches!(light, Light::Environment(_)))
                .map(|i| i as u32);
            let power = vec![1.0; lights.len()];
            LightTable::new(lights, &power, LightSelection::Power, vec![], environment)
        };
        let grey = Some(vec![Vec3::splat(0.5); 2]);
        let map = Some(vec![Vec3::ONE, Vec3::splat(3.0)]);
        let cases = [
            (vec![], EscapedLight::Dark),
            (vec![sky(Vec3::ZERO, None)], EscapedLight::Dark),
            (vec![sky(radiance, None)], EscapedLight::Uniform(radiance)),
            (
                vec![sky(radiance, grey)],
                EscapedLight::Uniform(radiance * 0.5),
            ),
            (vec![sky(radiance, map)], EscapedLight::Map),
            (vec![sun()], EscapedLight::SunDiscs),
            (vec![sky(radiance, None), sun()], EscapedLight::SunDiscs),
        ];
        for (lights, expected) in cases {
            let table = escaped(lights);
            assert_eq!(table.escaped_light(), expected);
            if let EscapedLight::Uniform(radiance) = expected {
                let (_, environment) = table.environment().expect("the sky");
                for direction in [Vec3::Z, Vec3::NEG_X, Vec3::new(0.3, -0.5, 0.8).normalize()] {
                    let lookup = environment.look_up(direction);
                    assert_eq!(lookup.radiance, radiance);
                    assert_eq!(environment.pdf_for_mis_of(&lookup), 0.0);
                }
            }
        }
    }
}
