//! Light shader classes. As in OpenRT (docs/design/seeds.md §1.1, "lighting only via light
//! shaders"), a light is a shader: `rtNewShaderClass(cid, "PointLight", NULL)`, `rtNewShader(id)`,
//! then its parameters are written by name with `rtParameter3f` or `rtParameter1f`. Each class
//! declares its parameters next to their documentation and defaults, like the surface classes of
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
    /// Reads it from a light of the class (three numbers; a number in the first; zeros for a
    /// texture): the class's default light gives the parameter's default.
    pub get: fn(&Light) -> [f32; 3],
    /// The values it accepts (each of three numbers).
    pub range: [f32; 2],
    /// What it does, and its units.
    pub doc: &'static str,
}

/// A built-in light class.
#[derive(Debug)]
pub(crate) struct LightClass {
    /// Its name, as given to `rtNewShaderClass`.
    pub name: &'static str,
    /// What it is.
    pub doc: &'static str,
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

/// A reader of field `$field` of lights of kind `$variant`, as three numbers.
macro_rules! getter {
    ($variant:ident, $field:ident) => {
        |light| match light {
            Light::$variant { $field, .. } => Values::values(*$field),
            _ => [0.0; 3],
        }
    };
}

/// A parameter `$name` writing three numbers into field `$field` of `$variant` lights.
macro_rules! triple {
    ($name:literal, $variant:ident, $field:ident, $range:expr, $doc:literal) => {
        LightParam { name: $name, set: Setter::Triple(field!($variant, $field)), get: getter!($variant, $field), range: $range, doc: $doc }
    };
}

/// A parameter `$name` writing one number into field `$field` of `$variant` lights.
macro_rules! number {
    ($name:literal, $variant:ident, $field:ident, $range:expr, $doc:literal) => {
        LightParam { name: $name, set: Setter::Number(field!($variant, $field)), get: getter!($variant, $field), range: $range, doc: $doc }
    };
}

/// A parameter's value as the three numbers introspection reports.
trait Values {
    fn values(self) -> [f32; 3];
}

impl Values for Vec3 {
    fn values(self) -> [f32; 3] {
        self.to_array()
    }
}

impl Values for f32 {
    fn values(self) -> [f32; 3] {
        [self, 0.0, 0.0]
    }
}

impl Values for Option<TextureId> {
    fn values(self) -> [f32; 3] {
        [0.0; 3]
    }
}

/// Any finite number.
const ANY: [f32; 2] = [f32::NEG_INFINITY, f32::INFINITY];
/// Light, which is never negative.
const POWER: [f32; 2] = [0.0, f32::INFINITY];

/// Every built-in light class: the OpenGL/VRML kinds OpenRT ships (point, spot, directional,
/// ambient) and the ray tracer's own (area, environment).
pub(crate) static LIGHT_CLASSES: &[LightClass] = &[
    LightClass {
        name: "PointLight",
        doc: "Light from a point, in every direction, falling off with the square of the distance.",
        default: Light::Point { position: Vec3::ZERO, intensity: Vec3::ONE },
        params: &[
            triple!("position", Point, position, ANY, "Where it is, in world space; default the origin."),
            triple!("intensity", Point, intensity, POWER, "Linear RGB radiant intensity: the irradiance on a surface facing it at distance 1 (a diffuse albedo rho there reflects radiance rho/pi times it); default 1."),
        ],
    },
    LightClass {
        name: "SpotLight",
        doc: "A point light shining into a cone, fading smoothly between the falloff and the cone's half-angles.",
        default: Light::Spot {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Z,
            intensity: Vec3::ONE,
            cone_degrees: 30.0,
            falloff_degrees: 25.0,
        },
        params: &[
            triple!("position", Spot, position, ANY, "Where it is, in world space; default the origin."),
            triple!("direction", Spot, direction, ANY, "The cone's axis, the way the light travels (any length); default -z."),
            triple!("intensity", Spot, intensity, POWER, "Linear RGB radiant intensity inside the cone, as PointLight's; default 1."),
            number!("cone", Spot, cone_degrees, [0.0, 90.0], "The cone's half-angle in degrees, above 0 and at most 90; default 30."),
            number!("falloff", Spot, falloff_degrees, [0.0, 90.0], "The half-angle in degrees where the light starts to fade, 0 to cone; default 25."),
        ],
    },
    LightClass {
        name: "DirectionalLight",
        doc: "Light from far away, arriving in parallel along one direction (a sun).",
        default: Light::Directional { direction: Vec3::NEG_Z, intensity: Vec3::ONE },
        params: &[
            triple!("direction", Directional, direction, ANY, "The way the light travels, towards the scene (the opposite of OpenGL's GL_POSITION w = 0 vector), any length; default -z."),
            triple!("intensity", Directional, intensity, POWER, "Linear RGB irradiance on a surface facing the light; default 1."),
        ],
    },
    LightClass {
        name: "AmbientLight",
        doc: "Light added to every surface, unshadowed, as OpenGL's ambient term.",
        default: Light::Ambient { intensity: Vec3::splat(0.2) },
        params: &[triple!("intensity", Ambient, intensity, POWER, "Linear RGB irradiance added to every surface; default 0.2, OpenGL's global ambient light.")],
    },
    LightClass {
        name: "AreaLight",
        doc: "A one-sided emitting parallelogram corner + s edge_u + t edge_v (s, t in [0, 1]), soft shadows in the distribution and path integrators.",
        default: Light::Area {
            corner: Vec3::new(-0.5, 1.0, -0.5),
            edge_u: Vec3::X,
            edge_v: Vec3::Z,
            radiance: Vec3::ONE,
        },
        params: &[
            triple!("corner", Area, corner, ANY, "One corner, in world space; default (-0.5, 1, -0.5)."),
            triple!("edge_u", Area, edge_u, ANY, "The first edge from the corner; default +x."),
            triple!("edge_v", Area, edge_v, ANY, "The second edge: the light leaves towards edge_u x edge_v; default +z (shining down)."),
            triple!("radiance", Area, radiance, POWER, "Linear RGB radiance it emits; default 1."),
        ],
    },
    LightClass {
        name: "EnvironmentLight",
        doc: "Light arriving from every direction (a sky), optionally from a latitude-longitude image.",
        default: Light::Environment { radiance: Vec3::ONE, map: None, rotate_degrees: 0.0 },
        params: &[
            triple!("radiance", Environment, radiance, POWER, "Linear RGB radiance from every direction, scaling the map if there is one; default 1."),
            LightParam {
                name: "map",
                set: Setter::Texture(field!(Environment, map)),
                get: getter!(Environment, map),
                range: [0.0, 0.0],
                doc: "A texture whose latitude-longitude image (top row straight up, +y) gives the radiance by direction; none by default.",
            },
            number!("rotate", Environment, rotate_degrees, ANY, "Turns the map about the up axis (+y) by this many degrees, counter-clockwise seen from above; default 0."),
        ],
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
        assert_eq!(light, Light::Environment { radiance: Vec3::ONE, map: Some(TextureId(3)), rotate_degrees: 0.0 });
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
