//! A garment's setup: everything besides its pieces and seams that decides how it simulates,
//! stored typed in the garment file (the manifest's `setup`) and applied to a simulation by
//! [`garment::setup`](crate::garment::setup), in one place.
//!
//! The add-on, the command line and pipeline scripts used to each turn "a garment plus its
//! painted data" into a configured simulation, and their copies disagreed (soft pin weights
//! rounded to 1/20 in one, to 0.01 in another; thickness 3 mm in one, 4 mm in two). Now they
//! gather inputs into a [`GarmentSetup`] and painted maps (the garment file's per-particle
//! parameters) and call `garment::apply_setup`:
//!
//! * **fabric per piece** ([`GarmentSetup::fabrics`]): the simulation is built with the first
//!   piece's fabric; where pieces differ, stretch and shear become per-triangle stiffness,
//!   bending per-triangle bending and density a per-particle mass scale (relative to the first);
//! * **painted maps** ([`maps`]), one value per vertex of a piece: `pin` (weight 0-1),
//!   `collision_level`, `friction_static`/`friction_kinetic` (override the cloth's friction,
//!   against colliders too), `mass_scale`, `bend_scale` (on each triangle, the mean over its
//!   vertices), and `position` (the piece as placed, which the build uses instead of placing
//!   and bending it again, so a garment placed by hand in Blender comes back exactly);
//! * **pins** ([`PinMode`]): `Attach` (the default) rides each pinned particle on the collider
//!   once the seams have met, at [`GarmentSetup::pin_stiffness`] times its weight (`garment::pin_groups`
//!   for the caller's bake loop, which attaches them); `Fixed` holds weight-1 pins in place and
//!   lighter ones softly, from the first frame;
//! * **collision**: thickness, self-collision with its radius, the cloth's friction (also
//!   against itself), and the collider's collision levels ([`ColliderLevels`]).
//!
//! Defaults are the constants below, read by every caller (the add-on's panel, the command
//! line, the docs), so that a default is written once.

use serde::{Deserialize, Serialize};

use crate::error::{Result, TailorError};
use crate::solver::{Fabric, SelfCollisionSettings, SelfContacts};

fn is_default_contacts(c: &SelfContacts) -> bool {
    *c == SelfContacts::default()
}

/// The contact model by its name, an unknown one refused naming the field and the names.
fn contacts_by_name<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<SelfContacts, D::Error> {
    let name = String::deserialize(d)?;
    SelfContacts::named(&name).map_err(|_| {
        let names: Vec<_> = SelfContacts::ALL.iter().map(|c| c.name()).collect();
        serde::de::Error::custom(format!(
            "setup.self_collision_contacts is '{name}': must be one of {}",
            names.join(", ")
        ))
    })
}

/// Default seam spring constant of a garment's seams, N/m per sewn pair.
///
/// A closed seam carries the tension of the cloth across it, so its gap is that tension over
/// this constant: the GarmentCode shirt on its body (8 substeps x 15 iterations) settles at
/// 3.1 mm with 1e3 N/m and 0.5 mm with 1e4 N/m (0.3 mm at 30 iterations), at the same cost
/// per frame (measured with `python -m tailor simulate`, docs/benchmarks.md). Ten times the
/// stretch of the default fabric's edge springs keeps seams stiffer than the cloth they join.
pub const DEFAULT_SEAM_STIFFNESS: f32 = 1.0e4;
/// Default collision thickness (the solver's own default), metres.
pub use crate::solver::DEFAULT_THICKNESS;
/// Default bending stiffness across a seam of bend factor 1, N·m.
pub const DEFAULT_SEAM_BEND_STIFFNESS: f32 = 1e-5;
/// Default stiffness of a weight-1 pin riding on the collider, N/m per particle: holds a
/// waistband against its ~1e-3 N weight.
pub const DEFAULT_PIN_STIFFNESS: f32 = 100.0;
/// Default friction of the cloth (against itself, and against colliders where painted).
pub const DEFAULT_FRICTION: Friction = Friction { static_friction: 0.5, kinetic_friction: 0.3 };
/// Pin weights at or above this are weight 1 (hard pins when [`PinMode::Fixed`]).
pub const HARD_PIN: f32 = 0.999;
/// Lighter pin weights are rounded to this many steps (a painted gradient gives at most 19
/// groups of attachments instead of one per distinct float).
pub const PIN_WEIGHT_STEPS: f32 = 20.0;

/// Names of the painted maps a setup applies (the garment file's per-particle parameters).
pub mod maps {
    /// Pin weight, 0 (free) to 1.
    pub const PIN: &str = "pin";
    /// Collision level (integer, see `solver::collide::levels`).
    pub const COLLISION_LEVEL: &str = "collision_level";
    pub const FRICTION_STATIC: &str = "friction_static";
    pub const FRICTION_KINETIC: &str = "friction_kinetic";
    /// Factor on the particle's mass.
    pub const MASS_SCALE: &str = "mass_scale";
    /// Factor on the bending stiffness (per triangle, the mean of its vertices).
    pub const BEND_SCALE: &str = "bend_scale";
    /// The piece's vertices as placed (three floats per vertex), used instead of its placement.
    pub const POSITION: &str = "position";
    /// Every name, in the order above.
    pub const ALL: [&str; 7] =
        [PIN, COLLISION_LEVEL, FRICTION_STATIC, FRICTION_KINETIC, MASS_SCALE, BEND_SCALE, POSITION];
}

/// How painted pins hold.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PinMode {
    /// Ride on the (first) collider once every seam has met (attached from the first frame,
    /// pins would hold the seams open).
    #[default]
    Attach,
    /// Held where the garment was placed, in world space, from the first frame.
    Fixed,
}

/// The axis pointing up in the coordinates a garment is placed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// glTF's, GarmentCode's, Maya's and Houdini's convention.
    Y,
    /// Blender's (the add-on's exports).
    Z,
}

/// Static and kinetic friction coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Friction {
    #[serde(rename = "static")]
    pub static_friction: f32,
    #[serde(rename = "kinetic")]
    pub kinetic_friction: f32,
}

/// Collision levels painted on the collider, run-length encoded (they come in large regions):
/// `[start, length, level]` runs over a mesh of `vertices` vertices, level 0 elsewhere.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColliderLevels {
    pub vertices: usize,
    pub runs: Vec<[i64; 3]>,
}

impl ColliderLevels {
    /// Run-length encoding of `levels` (zero runs left out).
    pub fn encode(levels: &[i32]) -> Self {
        let mut runs = Vec::new();
        let mut i = 0;
        while i < levels.len() {
            let mut j = i + 1;
            while j < levels.len() && levels[j] == levels[i] {
                j += 1;
            }
            if levels[i] != 0 {
                runs.push([i as i64, (j - i) as i64, levels[i] as i64]);
            }
            i = j;
        }
        ColliderLevels { vertices: levels.len(), runs }
    }

    /// The levels, one per vertex; runs outside the mesh or levels out of range are refused.
    pub fn decode(&self) -> Result<Vec<i32>> {
        let mut out = vec![0i32; self.vertices];
        for run @ [start, length, level] in &self.runs {
            let end = start.checked_add(*length);
            let Some(end) = end.filter(|&e| *start >= 0 && *length >= 0 && e <= self.vertices as i64) else {
                return Err(TailorError::setting(
                    "setup.collider_levels",
                    format!("{run:?}"),
                    format!("the run lies outside the mesh's {} vertices", self.vertices),
                ));
            };
            let level = i32::try_from(*level).map_err(|_| {
                TailorError::setting("setup.collider_levels", format!("{run:?}"), "the level is not a 32-bit integer")
            })?;
            out[*start as usize..end as usize].fill(level);
        }
        Ok(out)
    }
}

/// Everything besides pieces and seams that decides how a garment simulates (see the module).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GarmentSetup {
    /// The garment's name, for reports (empty: the file's name).
    pub name: String,
    /// Fabric of each piece, in garment order; empty: the default fabric for every piece. Read
    /// as values or by a library name ([`crate::fabrics::deserialize_entries`]).
    #[serde(deserialize_with = "crate::fabrics::deserialize_entries")]
    pub fabrics: Vec<Fabric>,
    /// Collision thickness, metres.
    pub thickness: f32,
    /// The cloth's friction: against itself, and against colliders where painted.
    pub friction: Friction,
    pub self_collision: bool,
    /// Self-collision sphere radius, metres; 0: half the mean rest edge (spheres), the
    /// collision thickness default (triangles: the distance kept from a triangle).
    pub self_collision_radius: f32,
    /// The cloth-cloth contact model; not written while it is the default (older files read
    /// and write unchanged).
    #[serde(skip_serializing_if = "is_default_contacts", deserialize_with = "contacts_by_name")]
    pub self_collision_contacts: SelfContacts,
    pub pin_mode: PinMode,
    /// N/m per weight-1 pin ([`PinMode::Attach`], and soft pins when fixed).
    pub pin_stiffness: f32,
    /// Spring constant of a seam of stiffness factor 1, N/m.
    pub seam_stiffness: f32,
    /// Bending stiffness across a seam of bend factor 1.
    pub seam_bend_stiffness: f32,
    /// Collision levels of the (first) collider, when painted.
    pub collider_levels: Option<ColliderLevels>,
    /// The up axis of the coordinates the pieces are placed in (None: not stated). A collider
    /// with another up axis is turned into the garment's (`tailor simulate`).
    pub up: Option<UpAxis>,
}

impl Default for GarmentSetup {
    fn default() -> Self {
        GarmentSetup {
            name: String::new(),
            fabrics: Vec::new(),
            thickness: DEFAULT_THICKNESS,
            friction: DEFAULT_FRICTION,
            self_collision: false,
            self_collision_radius: 0.0,
            self_collision_contacts: SelfContacts::default(),
            pin_mode: PinMode::Attach,
            pin_stiffness: DEFAULT_PIN_STIFFNESS,
            seam_stiffness: DEFAULT_SEAM_STIFFNESS,
            seam_bend_stiffness: DEFAULT_SEAM_BEND_STIFFNESS,
            collider_levels: None,
            up: None,
        }
    }
}

fn check(name: &'static str, v: f32, ok: bool, rule: &str) -> Result<()> {
    if ok && v.is_finite() {
        Ok(())
    } else {
        Err(TailorError::setting(name, v, rule.to_string()))
    }
}

impl GarmentSetup {
    /// Checks every value, for a garment of `pieces` pieces.
    pub fn validate(&self, pieces: usize) -> Result<()> {
        if !self.fabrics.is_empty() && self.fabrics.len() != pieces {
            return Err(TailorError::setting(
                "setup.fabrics",
                self.fabrics.len(),
                format!("one fabric per piece: the garment has {pieces} pieces"),
            ));
        }
        for (i, f) in self.fabrics.iter().enumerate() {
            f.validate().map_err(|e| TailorError::setting("setup.fabrics", i, format!("piece {i}'s fabric: {e}")))?;
        }
        check("setup.thickness", self.thickness, self.thickness > 0.0, "must be positive")?;
        check(
            "setup.friction.static",
            self.friction.static_friction,
            self.friction.static_friction >= 0.0,
            "must be 0 or more",
        )?;
        check(
            "setup.friction.kinetic",
            self.friction.kinetic_friction,
            self.friction.kinetic_friction >= 0.0,
            "must be 0 or more",
        )?;
        let r = self.self_collision_radius;
        check("setup.self_collision_radius", r, r >= 0.0, "must be 0 (automatic) or a positive length")?;
        check("setup.pin_stiffness", self.pin_stiffness, self.pin_stiffness > 0.0, "must be positive")?;
        check("setup.seam_stiffness", self.seam_stiffness, self.seam_stiffness >= 0.0, "must be 0 or more")?;
        check(
            "setup.seam_bend_stiffness",
            self.seam_bend_stiffness,
            self.seam_bend_stiffness >= 0.0,
            "must be 0 or more",
        )?;
        if let Some(l) = &self.collider_levels {
            l.decode()?;
        }
        Ok(())
    }

    /// The fabric the simulation is built with: the first piece's, or the default.
    pub fn base_fabric(&self) -> Fabric {
        self.fabrics.first().copied().unwrap_or_default()
    }

    /// The self-collision settings: on or off, the radius (0: automatic), the cloth's friction.
    pub fn self_collision_settings(&self) -> SelfCollisionSettings {
        let r = self.self_collision_radius;
        SelfCollisionSettings {
            enabled: self.self_collision,
            radius: (r > 0.0).then_some(r),
            contacts: self.self_collision_contacts,
            static_friction: self.friction.static_friction,
            kinetic_friction: self.friction.kinetic_friction,
        }
    }

    /// The value of map `name` where it is not painted.
    pub fn unpainted(&self, name: &str) -> f32 {
        match name {
            maps::MASS_SCALE | maps::BEND_SCALE => 1.0,
            maps::FRICTION_STATIC => self.friction.static_friction,
            maps::FRICTION_KINETIC => self.friction.kinetic_friction,
            _ => 0.0,
        }
    }
}
