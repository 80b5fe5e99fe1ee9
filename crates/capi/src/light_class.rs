//! Light shader classes. As in OpenRT (DIGEST §1.1, "lighting only via light shaders"), a light
//! is a shader: `rtNewShaderClass(cid, "PointLight", NULL)`, `rtNewShader(id)`, then its
//! parameters are written by name with `rtParameter3f` or `rtParameter1f`. Each class declares
//! its parameters next to their documentation and defaults, like the surface classes of
//! `raystage-scene`. Positions and directions are in world space.

use glam::Vec3;
use raystage_scene::{Light, TextureId};

/// How a light parameter is written.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Setter {
    /// One number (`rtParameter1f`).
    Number(fn(&mut Light, f32)),
    /// Three numbers: a position, a direction or a colour (`rtParameter3f`).
    Triple(fn(&mut Light, Vec3)),
    /// A texture, or none (`rtParameterTexture`).
    Texture(fn(&mut Light, Option<TextureId>)),
}

/// A parameter of a light class.
#[derive(Debug)]
pub(crate) struct LightParam {
    /// Its name, as given to `rtParameterHandle`.
    pub name: &'static str,
    /// Writes a value into a light of the parameter's class.
    pub set: Setter,
}

/// A built-in light class.
#[derive(Debug)]
pub(crate) struct LightClass {
    /// Its name, as given to `rtNewShaderClass`.
    pub name: &'static str,
    /// The light a new shader of the class starts as.
    pub default: Light,
    /// The parameters it exports.
    pub params: &'static [LightParam],
}

impl PartialEq for LightClass {
    fn eq(&self, other: &LightClass) -> bool {
        self.name == other.name
    }
}

/// A setter of field `$field` of lights of kind `$variant`.
macro_rules! field {
    ($variant:ident, $field:ident) => {
        |light, value| {
            if let Light::$variant { $field, .. } = light {
                *$field = value;
            }
        }
    };
}

/// A parameter `$name` writing three numbers into field `$field` of `$variant` lights.
macro_rules! triple {
    ($name:literal, $variant:ident, $field:ident) => {
        LightParam { name: $name, set: Setter::Triple(field!($variant, $field)) }
    };
}

/// Every built-in light class: the OpenGL/VRML kinds OpenRT ships (point, spot, directional,
/// ambient) and the ray tracer's own (area, environment).
pub(crate) static LIGHT_CLASSES: &[LightClass] = &[
    LightClass {
        name: "PointLight",
        // "position": where it is, default the origin. "intensity": linear RGB radiant
        // intensity (the irradiance at distance 1), default 1.
        default: Light::Point { position: Vec3::ZERO, intensity: Vec3::ONE },
        params: &[triple!("position", Point, position), triple!("intensity", Point, intensity)],
    },
    LightClass {
        name: "SpotLight",
        // As "PointLight", plus "direction": the cone's axis, default −z; "cone": the cone's
        // half-angle in degrees, in (0, 90], default 30; "falloff": the half-angle where the
        // light starts to fade, in [0, cone], default 25.
        default: Light::Spot {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Z,
            intensity: Vec3::ONE,
            cone_degrees: 30.0,
            falloff_degrees: 25.0,
        },
        params: &[
            triple!("position", Spot, position),
            triple!("direction", Spot, direction),
            triple!("intensity", Spot, intensity),
            LightParam { name: "cone", set: Setter::Number(field!(Spot, cone_degrees)) },
            LightParam { name: "falloff", set: Setter::Number(field!(Spot, falloff_degrees)) },
        ],
    },
    LightClass {
        name: "DirectionalLight",
        // "direction": the way the light travels (towards the scene), any length, default −z.
        // "intensity": linear RGB irradiance on a surface facing the light, default 1.
        default: Light::Directional { direction: Vec3::NEG_Z, intensity: Vec3::ONE },
        params: &[triple!("direction", Directional, direction), triple!("intensity", Directional, intensity)],
    },
    LightClass {
        name: "AmbientLight",
        // "intensity": irradiance added to every surface, unshadowed; default 0.2, OpenGL's
        // global ambient light.
        default: Light::Ambient { intensity: Vec3::splat(0.2) },
        params: &[triple!("intensity", Ambient, intensity)],
    },
    LightClass {
        name: "AreaLight",
        // The parallelogram corner + s·edge_u + t·edge_v (s, t in [0, 1]), emitting towards
        // edge_u × edge_v with "radiance". Default: a unit square at height 1 shining down.
        default: Light::Area {
            corner: Vec3::new(-0.5, 1.0, -0.5),
            edge_u: Vec3::X,
            edge_v: Vec3::Z,
            radiance: Vec3::ONE,
        },
        params: &[
            triple!("corner", Area, corner),
            triple!("edge_u", Area, edge_u),
            triple!("edge_v", Area, edge_v),
            triple!("radiance", Area, radiance),
        ],
    },
    LightClass {
        name: "EnvironmentLight",
        // "radiance": light arriving from every direction, default 1. "map": a texture whose
        // latitude-longitude image (top row straight up, +y) the radiance scales; none by default.
        default: Light::Environment { radiance: Vec3::ONE, map: None },
        params: &[triple!("radiance", Environment, radiance), LightParam { name: "map", set: Setter::Texture(field!(Environment, map)) }],
    },
];

/// The light class called `name`.
pub(crate) fn light_class(name: &str) -> Option<&'static LightClass> {
    LIGHT_CLASSES.iter().find(|c| c.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(class: &LightClass, light: &mut Light, name: &str, value: Vec3) {
        match class.params.iter().find(|p| p.name == name).expect("a parameter").set {
            Setter::Triple(set) => set(light, value),
            Setter::Number(set) => set(light, value.x),
            Setter::Texture(_) => panic!("`{name}` takes a texture, not numbers"),
        }
    }

    #[test]
    fn parameters_write_their_own_field() {
        let point = light_class("PointLight").unwrap();
        let mut light = point.default;
        write(point, &mut light, "position", Vec3::new(1.0, 2.0, 3.0));
        write(point, &mut light, "intensity", Vec3::splat(4.0));
        assert_eq!(light, Light::Point { position: Vec3::new(1.0, 2.0, 3.0), intensity: Vec3::splat(4.0) });
        let spot = light_class("SpotLight").unwrap();
        let mut light = spot.default;
        write(spot, &mut light, "cone", Vec3::splat(45.0));
        let Light::Spot { cone_degrees, falloff_degrees, .. } = light else { panic!("a spot light") };
        assert_eq!((cone_degrees, falloff_degrees), (45.0, 25.0));
        assert!(light_class("Sun").is_none());
    }

    #[test]
    fn an_environment_map_is_a_texture_parameter() {
        let environment = light_class("EnvironmentLight").unwrap();
        let Setter::Texture(set) = environment.params.iter().find(|p| p.name == "map").unwrap().set else { panic!("a texture parameter") };
        let mut light = environment.default;
        set(&mut light, Some(TextureId(3)));
        assert_eq!(light, Light::Environment { radiance: Vec3::ONE, map: Some(TextureId(3)) });
        set(&mut light, None);
        assert_eq!(light, environment.default);
    }

    #[test]
    fn defaults_are_valid_lights_of_distinct_names() {
        for class in LIGHT_CLASSES {
            class.default.validate().unwrap();
            assert_eq!(LIGHT_CLASSES.iter().filter(|c| c.name == class.name).count(), 1);
        }
    }
}
