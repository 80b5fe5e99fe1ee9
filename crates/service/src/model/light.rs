//! Lights in JSON, by the C ABI's light class names and parameter names.

use glam::Vec3;
use raystage_scene::Light;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::error::{Error, Result};
use crate::model::refs::Ref;

/// A linear RGB colour: three numbers, or one for a grey.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "a number or three numbers (a colour)")]
pub enum Rgb {
    /// The same value in every channel.
    Grey(f32),
    /// Red, green, blue.
    Rgb([f32; 3]),
}

impl Rgb {
    /// The colour as a vector.
    pub(crate) fn vec(self) -> Vec3 {
        match self {
            Rgb::Grey(g) => Vec3::splat(g),
            Rgb::Rgb(c) => Vec3::from(c),
        }
    }
}

/// The light classes, with the parameters each takes, as in the C ABI.
pub const LIGHT_CLASSES: &[(&str, &[&str])] = &[
    ("PointLight", &["position", "intensity"]),
    ("SpotLight", &["position", "direction", "intensity", "cone", "falloff"]),
    ("DirectionalLight", &["direction", "intensity"]),
    ("AmbientLight", &["intensity"]),
    ("AreaLight", &["corner", "edge_u", "edge_v", "radiance"]),
    ("EnvironmentLight", &["radiance", "map", "rotate"]),
];

/// A light: a class and the parameters it takes; parameters left out keep the class default
/// (as a new light shader of the C ABI). A parameter the class does not take is an error.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct LightSpec {
    /// In a batch, a name later commands can use for this light instead of its id.
    #[serde(skip_serializing)]
    pub label: Option<String>,
    /// `PointLight`, `SpotLight`, `DirectionalLight`, `AmbientLight`, `AreaLight` or
    /// `EnvironmentLight`.
    pub class: String,
    /// Where (point, spot); default the origin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position: Option<[f32; 3]>,
    /// The way the light shines (spot: the cone's axis; directional: towards the scene);
    /// default −z.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f32; 3]>,
    /// Linear RGB intensity (point, spot: irradiance at distance 1; directional: irradiance;
    /// ambient: added irradiance); default 1 (ambient 0.2).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub intensity: Option<Rgb>,
    /// Spot: half-angle of the cone in degrees, in (0, 90]; default 30.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cone: Option<f32>,
    /// Spot: half-angle where the fall-off starts, in [0, cone]; default 25.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub falloff: Option<f32>,
    /// Area: one corner of the emitting parallelogram; default (−0.5, 1, −0.5).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub corner: Option<[f32; 3]>,
    /// Area: first edge from the corner; default +x.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edge_u: Option<[f32; 3]>,
    /// Area: second edge; it emits towards edge_u × edge_v; default +z (so it shines down).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edge_v: Option<[f32; 3]>,
    /// Area, environment: emitted radiance, linear RGB; default 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radiance: Option<Rgb>,
    /// Environment: a latitude-longitude image texture (`/scenes/{scene}/textures`) whose
    /// colour, scaled by `radiance`, is the light arriving from each direction; by id, or in a
    /// batch by the label of a texture an earlier command created. Default (and null): none,
    /// the same radiance from everywhere.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub map: Option<Ref>,
    /// Environment: turns the map about the up axis (+y) by this many degrees,
    /// counter-clockwise seen from above; default 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotate: Option<f32>,
}

/// A light with its id.
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct LightInfo {
    /// The light's id.
    pub id: u32,
    /// The light.
    #[serde(flatten)]
    pub light: LightSpec,
}

impl LightSpec {
    /// The scene's light, checked (422 naming the field), without its map: `map` is a
    /// reference, which the caller resolves (a batch resolves it as it applies its commands).
    pub fn to_light(&self) -> Result<Light> {
        let Some((class, params)) = LIGHT_CLASSES.iter().find(|(name, _)| *name == self.class) else {
            let names: Vec<&str> = LIGHT_CLASSES.iter().map(|(n, _)| *n).collect();
            return Err(Error::unprocessable(Some("class".into()), format!("unknown light class `{}`: expected one of {}", self.class, names.join(", "))));
        };
        for (name, given) in self.given() {
            if given && !params.contains(&name) {
                return Err(Error::unprocessable(Some(name.into()), format!("{class} has no parameter `{name}`: it takes {}", params.join(", "))));
            }
        }
        let v = |p: Option<[f32; 3]>, default: Vec3| p.map_or(default, Vec3::from);
        let c = |p: Option<Rgb>, default: Vec3| p.map_or(default, Rgb::vec);
        let light = match *class {
            "PointLight" => Light::Point { position: v(self.position, Vec3::ZERO), intensity: c(self.intensity, Vec3::ONE) },
            "SpotLight" => Light::Spot {
                position: v(self.position, Vec3::ZERO),
                direction: v(self.direction, Vec3::NEG_Z),
                intensity: c(self.intensity, Vec3::ONE),
                cone_degrees: self.cone.unwrap_or(30.0),
                falloff_degrees: self.falloff.unwrap_or(25.0f32.min(self.cone.unwrap_or(30.0))),
            },
            "DirectionalLight" => Light::Directional { direction: v(self.direction, Vec3::NEG_Z), intensity: c(self.intensity, Vec3::ONE) },
            "AmbientLight" => Light::Ambient { intensity: c(self.intensity, Vec3::splat(0.2)) },
            "AreaLight" => Light::Area {
                corner: v(self.corner, Vec3::new(-0.5, 1.0, -0.5)),
                edge_u: v(self.edge_u, Vec3::X),
                edge_v: v(self.edge_v, Vec3::Z),
                radiance: c(self.radiance, Vec3::ONE),
            },
            _ => Light::Environment { radiance: c(self.radiance, Vec3::ONE), map: None, rotate_degrees: self.rotate.unwrap_or(0.0) },
        };
        light.validate().map_err(|e| {
            let e = Error::from(e).without_prefix("light.");
            // The scene calls the spot angles and the environment's turn by their full names.
            match e.detail.field.as_deref() {
                Some("cone_degrees") => Error { detail: crate::error::ErrorDetail { field: Some("cone".into()), ..e.detail }, ..e },
                Some("falloff_degrees") => Error { detail: crate::error::ErrorDetail { field: Some("falloff".into()), ..e.detail }, ..e },
                Some("rotate_degrees") => Error { detail: crate::error::ErrorDetail { field: Some("rotate".into()), ..e.detail }, ..e },
                _ => e,
            }
        })?;
        Ok(light)
    }

    /// Which parameters were given.
    fn given(&self) -> [(&'static str, bool); 11] {
        [
            ("position", self.position.is_some()),
            ("direction", self.direction.is_some()),
            ("intensity", self.intensity.is_some()),
            ("cone", self.cone.is_some()),
            ("falloff", self.falloff.is_some()),
            ("corner", self.corner.is_some()),
            ("edge_u", self.edge_u.is_some()),
            ("edge_v", self.edge_v.is_some()),
            ("radiance", self.radiance.is_some()),
            ("map", self.map.is_some()),
            ("rotate", self.rotate.is_some()),
        ]
    }

    /// A scene light as JSON.
    pub fn from_light(light: &Light) -> LightSpec {
        let a = |v: Vec3| Some(v.to_array());
        let c = |v: Vec3| Some(Rgb::Rgb(v.to_array()));
        let class = |name: &str| LightSpec { class: name.into(), ..LightSpec::default() };
        match *light {
            Light::Point { position, intensity } => LightSpec { position: a(position), intensity: c(intensity), ..class("PointLight") },
            Light::Spot { position, direction, intensity, cone_degrees, falloff_degrees } => LightSpec {
                position: a(position),
                direction: a(direction),
                intensity: c(intensity),
                cone: Some(cone_degrees),
                falloff: Some(falloff_degrees),
                ..class("SpotLight")
            },
            Light::Directional { direction, intensity } => LightSpec { direction: a(direction), intensity: c(intensity), ..class("DirectionalLight") },
            Light::Ambient { intensity } => LightSpec { intensity: c(intensity), ..class("AmbientLight") },
            Light::Area { corner, edge_u, edge_v, radiance } => {
                LightSpec { corner: a(corner), edge_u: a(edge_u), edge_v: a(edge_v), radiance: c(radiance), ..class("AreaLight") }
            }
            Light::Environment { radiance, map, rotate_degrees } => {
                LightSpec { radiance: c(radiance), map: map.map(|t| Ref::Id(t.0)), rotate: Some(rotate_degrees), ..class("EnvironmentLight") }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_class_round_trips_with_its_defaults() {
        for (class, _) in LIGHT_CLASSES {
            let light = LightSpec { class: class.to_string(), ..LightSpec::default() }.to_light().unwrap();
            assert_eq!(LightSpec::from_light(&light).to_light().unwrap(), light, "{class}");
        }
    }

    #[test]
    fn wrong_parameters_and_values_name_the_field() {
        let spot_on_point = LightSpec { class: "PointLight".into(), cone: Some(10.0), ..LightSpec::default() };
        assert_eq!(spot_on_point.to_light().unwrap_err().detail.field.as_deref(), Some("cone"));
        let wide = LightSpec { class: "SpotLight".into(), cone: Some(120.0), ..LightSpec::default() };
        assert_eq!(wide.to_light().unwrap_err().detail.field.as_deref(), Some("cone"));
        let dark = LightSpec { class: "PointLight".into(), intensity: Some(Rgb::Rgb([-1.0, 0.0, 0.0])), ..LightSpec::default() };
        assert_eq!(dark.to_light().unwrap_err().detail.field.as_deref(), Some("intensity"));
        let turned = LightSpec { class: "EnvironmentLight".into(), rotate: Some(f32::INFINITY), ..LightSpec::default() };
        assert_eq!(turned.to_light().unwrap_err().detail.field.as_deref(), Some("rotate"));
        let unknown = LightSpec { class: "Sun".into(), ..LightSpec::default() };
        assert_eq!(unknown.to_light().unwrap_err().detail.field.as_deref(), Some("class"));
    }

    #[test]
    fn an_environment_map_is_shown_and_only_environment_lights_take_one() {
        let mapped = Light::Environment { radiance: Vec3::splat(2.0), map: Some(raystage_scene::TextureId(4)), rotate_degrees: 90.0 };
        let json = serde_json::to_value(LightSpec::from_light(&mapped)).unwrap();
        assert_eq!(json, serde_json::json!({ "class": "EnvironmentLight", "radiance": [2.0, 2.0, 2.0], "map": 4, "rotate": 90.0 }));
        let point = LightSpec { class: "PointLight".into(), map: Some(Ref::Id(4)), ..LightSpec::default() };
        assert_eq!(point.to_light().unwrap_err().detail.field.as_deref(), Some("map"));
    }
}
