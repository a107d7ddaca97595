//! Reading a version-1 garment file's setup.
//!
//! Version 1 had no typed setup: the sample garments and the add-on's export kept theirs in the
//! free-form settings, under `tailor_sample` (`name`, `fabric_per_piece`, `thickness`,
//! `self_collision`, `self_collision_radius`, `friction_static`, `friction_kinetic`,
//! `collider_levels`), and the command line applied it with its own defaults. Those keys
//! become the typed [`GarmentSetup`] with the values version 1 simulated with (the
//! self-collision friction of the solver, 0.3/0.2, where none was recorded; pins riding on
//! the collider at 100 N/m); keys it did not know (`character`, `up`) stay in the settings.

use std::collections::BTreeMap;

use serde_json::{Map, Value};

use super::setup::{ColliderLevels, Friction, GarmentSetup, PinMode, DEFAULT_PIN_STIFFNESS};
use crate::error::{Result, TailorError};
use crate::solver::{Fabric, SelfCollisionSettings};

/// The settings key version 1 kept its setup under.
pub const V1_KEY: &str = "tailor_sample";

/// The typed setup of a version-1 file's `settings`, taking the keys it used out of them.
pub fn setup_of_v1(settings: &mut BTreeMap<String, Value>, file: &str) -> Result<GarmentSetup> {
    let mut setup = GarmentSetup {
        // The friction version 1 gave self-collision when the file recorded none: the solver's.
        friction: {
            let d = SelfCollisionSettings::default();
            Friction { static_friction: d.static_friction, kinetic_friction: d.kinetic_friction }
        },
        pin_mode: PinMode::Attach,
        pin_stiffness: DEFAULT_PIN_STIFFNESS,
        ..GarmentSetup::default()
    };
    let Some(Value::Object(old)) = settings.get(V1_KEY).cloned() else {
        return Ok(setup);
    };
    let bad = |key: &str, why: &str| TailorError::parse(file, format!("settings.{V1_KEY}.{key}"), why.to_string());
    let mut rest = Map::new();
    for (key, v) in old {
        let num = || v.as_f64().map(|x| x as f32).ok_or_else(|| bad(&key, "expected a number"));
        match key.as_str() {
            "name" => setup.name = v.as_str().ok_or_else(|| bad(&key, "expected a string"))?.to_string(),
            "thickness" => setup.thickness = num()?,
            "self_collision" => {
                setup.self_collision = v.as_bool().ok_or_else(|| bad(&key, "expected true or false"))?
            }
            "self_collision_radius" => setup.self_collision_radius = num()?,
            "friction_static" => setup.friction.static_friction = num()?,
            "friction_kinetic" => setup.friction.kinetic_friction = num()?,
            "fabric_per_piece" => setup.fabrics = fabrics(&v).map_err(|why| bad(&key, &why))?,
            "collider_levels" => {
                setup.collider_levels =
                    Some(serde_json::from_value::<ColliderLevels>(v).map_err(|e| bad(&key, &e.to_string()))?)
            }
            _ => {
                rest.insert(key, v);
            }
        }
    }
    if rest.is_empty() {
        settings.remove(V1_KEY);
    } else {
        settings.insert(V1_KEY.into(), Value::Object(rest));
    }
    Ok(setup)
}

/// Version 1's fabric list: a piece's missing keys took the first piece's.
fn fabrics(v: &Value) -> std::result::Result<Vec<Fabric>, String> {
    let list = v.as_array().ok_or("expected a list of fabrics")?;
    let first = list.first().and_then(Value::as_object).cloned().unwrap_or_default();
    list.iter()
        .map(|f| {
            let mut merged = first.clone();
            merged.extend(f.as_object().ok_or("expected a fabric object")?.clone());
            serde_json::from_value::<Fabric>(Value::Object(merged)).map_err(|e| e.to_string())
        })
        .collect()
}
