//! Applying a garment's [`GarmentSetup`] (fabric per piece, painted maps, pins, collision) to
//! a simulation built from it: the one place where "a garment plus its painted data" becomes a
//! configured solver (the add-on, the command line and scripts all come here through
//! `tailor.Garment.build_simulation`). The setup's data and defaults are in
//! [`garment_file::setup`](crate::garment_file::setup).

use crate::error::{Result, TailorError};
use crate::garment_file::setup::{maps, PinMode, HARD_PIN, PIN_WEIGHT_STEPS};
use crate::garment_file::{Garment, ParticleValues};
use crate::solver::{Attachment, Fabric, Simulation};

/// Particles attached together at one stiffness.
#[derive(Debug, Clone, PartialEq)]
pub struct PinGroup {
    pub particles: Vec<u32>,
    /// N/m per particle.
    pub stiffness: f32,
}

/// What applying a setup left to the caller.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Applied {
    /// Pins to attach to the collider once the seams have met ([`PinMode::Attach`]).
    pub attach: Vec<PinGroup>,
    /// Painted data left out (a map for another mesh), pins held in place for want of a
    /// collider: said to the user, not an error.
    pub warnings: Vec<String>,
}

/// Where each piece's particles start in the sewn cloth, and how many each has.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub offsets: Vec<u32>,
    pub vertices: Vec<usize>,
    pub triangles: Vec<usize>,
}

impl Layout {
    /// The layout of piece meshes sewn in order (the sewn cloth concatenates them).
    pub fn of_meshes(meshes: &[crate::triangulate::PieceMesh]) -> Self {
        let vertices: Vec<usize> = meshes.iter().map(|m| m.rest.len()).collect();
        let offsets = vertices.iter().scan(0u32, |o, &n| Some(std::mem::replace(o, *o + n as u32))).collect();
        Layout { offsets, vertices, triangles: meshes.iter().map(|m| m.triangles.len()).collect() }
    }

    pub fn particles(&self) -> usize {
        self.vertices.iter().sum()
    }
}

/// The painted values of map `name` over all particles, `unpainted` elsewhere, and whether any
/// piece has it. A map whose piece has another vertex count (re-triangulated since it was
/// painted) is left out with a warning.
fn painted(
    garment: &Garment,
    layout: &Layout,
    name: &str,
    unpainted: f32,
    warnings: &mut Vec<String>,
) -> Result<(Vec<f32>, bool)> {
    let mut out = vec![unpainted; layout.particles()];
    let mut any = false;
    for p in garment.particle_params.iter().filter(|p| p.name == name) {
        let Some(&count) = layout.vertices.get(p.piece) else {
            warnings.push(format!(
                "painted '{name}' of piece {} (the garment has {} pieces): left out",
                p.piece,
                layout.vertices.len()
            ));
            continue;
        };
        if p.values.len() != count {
            warnings.push(format!(
                "painted '{name}' of piece {} has {} values for {count} vertices (re-triangulated since?): left out",
                p.piece,
                p.values.len()
            ));
            continue;
        }
        let o = layout.offsets[p.piece] as usize;
        let dst = &mut out[o..o + count];
        match &p.values {
            ParticleValues::F32(v) => dst.copy_from_slice(v),
            ParticleValues::I32(v) => dst.iter_mut().zip(v).for_each(|(d, &x)| *d = x as f32),
            ParticleValues::Bool(v) => dst.iter_mut().zip(v).for_each(|(d, &x)| *d = x as u8 as f32),
            ParticleValues::Vec3(_) => {
                return Err(TailorError::setting(
                    "painted map",
                    name,
                    format!("piece {} holds 3 values per vertex, expected 1", p.piece),
                ))
            }
        }
        if let Some(bad) = dst.iter().position(|x| !x.is_finite()) {
            return Err(TailorError::setting(
                "painted map",
                name,
                format!("piece {} vertex {bad} is {}: values must be finite", p.piece, dst[bad]),
            ));
        }
        any = true;
    }
    Ok((out, any))
}

/// Groups of pinned particles by weight: weight 1 (at or above [`HARD_PIN`]) first, then the
/// lighter weights rounded to 1/[`PIN_WEIGHT_STEPS`], lightest first; weight 0 is no pin.
/// Returns (weight, particles).
pub fn pin_weights(weights: &[f32]) -> Vec<(f32, Vec<u32>)> {
    let step = |w: f32| {
        if w >= HARD_PIN {
            PIN_WEIGHT_STEPS as i32
        } else {
            (w.clamp(0.0, 1.0) * PIN_WEIGHT_STEPS).round() as i32
        }
    };
    let mut by_step: Vec<Vec<u32>> = vec![Vec::new(); PIN_WEIGHT_STEPS as usize + 1];
    for (i, &w) in weights.iter().enumerate() {
        by_step[step(w) as usize].push(i as u32);
    }
    let order = std::iter::once(PIN_WEIGHT_STEPS as usize).chain(1..PIN_WEIGHT_STEPS as usize);
    let mut out = Vec::new();
    for s in order {
        let particles = std::mem::take(&mut by_step[s]);
        if !particles.is_empty() {
            out.push((s as f32 / PIN_WEIGHT_STEPS, particles));
        }
    }
    out
}

/// The painted pins grouped by weight ([`pin_weights`] of the `pin` map).
pub fn painted_pins(garment: &Garment, layout: &Layout) -> Result<Vec<(f32, Vec<u32>)>> {
    let (w, _) = painted(garment, layout, maps::PIN, 0.0, &mut Vec::new())?;
    Ok(pin_weights(&w))
}

/// The groups [`PinMode::Attach`] attaches to the collider once the seams have met: each
/// painted weight at `pin_stiffness` times the weight (empty when pins are fixed).
pub fn pin_groups(garment: &Garment, layout: &Layout) -> Result<Vec<PinGroup>> {
    if garment.setup.pin_mode != PinMode::Attach {
        return Ok(Vec::new());
    }
    Ok(painted_pins(garment, layout)?
        .into_iter()
        .map(|(weight, particles)| PinGroup { particles, stiffness: garment.setup.pin_stiffness * weight })
        .collect())
}

/// Applies `garment`'s setup and painted maps to `sim`, built from it with
/// [`GarmentSetup::base_fabric`](crate::garment_file::GarmentSetup::base_fabric) (pieces laid
/// out as `layout` says): [`apply_fabric`], [`apply_friction`], [`apply_levels`],
/// [`apply_collision`], then the pins. `ride`: a collider is there for [`PinMode::Attach`]
/// pins to ride on (they are returned for the caller's bake loop to attach once the seams have
/// met); without one, or when the setup fixes them, weight-1 pins are held where they are and
/// lighter ones softly at `pin_stiffness` times their weight. The colliders' own levels are
/// the caller's (`ColliderLevels`).
pub fn apply_setup(sim: &mut Simulation, garment: &Garment, layout: &Layout, ride: bool) -> Result<Applied> {
    let setup = &garment.setup;
    setup.validate(layout.vertices.len())?;
    let mut warnings = Vec::new();
    apply_fabric(sim, garment, layout, &mut warnings)?;
    apply_friction(sim, garment, layout, &mut warnings)?;
    apply_levels(sim, garment, layout, &mut warnings)?;
    apply_collision(sim, garment)?;
    let (weights, _) = painted(garment, layout, maps::PIN, 0.0, &mut warnings)?;
    let groups = pin_weights(&weights);
    let mut attach = Vec::new();
    if setup.pin_mode == PinMode::Attach && ride {
        attach = groups
            .into_iter()
            .map(|(weight, particles)| PinGroup { particles, stiffness: setup.pin_stiffness * weight })
            .collect();
    } else {
        if setup.pin_mode == PinMode::Attach && !groups.is_empty() {
            warnings.push("pins are held in place: there is no collider for them to ride on".into());
        }
        for (weight, particles) in groups {
            if weight >= 1.0 {
                sim.pin(&particles, None)?;
            } else {
                for p in particles {
                    let target = sim.positions().get(p as usize).to_array();
                    sim.add_attachment(Attachment { particle: p, target, weight: setup.pin_stiffness * weight })?;
                }
            }
        }
    }
    Ok(Applied { attach, warnings })
}

/// Thickness and self-collision (radius, the cloth's friction against itself).
pub fn apply_collision(sim: &mut Simulation, garment: &Garment) -> Result<()> {
    sim.set_thickness(garment.setup.thickness)?;
    sim.set_self_collision(garment.setup.self_collision_settings())
}

/// Painted friction: where any piece has it, every particle's own friction (painted, else the
/// setup's), against colliders too; otherwise none (the colliders' and self-collision's).
pub fn apply_friction(
    sim: &mut Simulation,
    garment: &Garment,
    layout: &Layout,
    warnings: &mut Vec<String>,
) -> Result<()> {
    let setup = &garment.setup;
    let (fs, a) = painted(garment, layout, maps::FRICTION_STATIC, setup.unpainted(maps::FRICTION_STATIC), warnings)?;
    let (fk, b) = painted(garment, layout, maps::FRICTION_KINETIC, setup.unpainted(maps::FRICTION_KINETIC), warnings)?;
    sim.set_particle_friction(if a || b { Some((&fs, &fk)) } else { None })
}

/// Painted collision levels (level 0 where unpainted), when any piece has them.
pub fn apply_levels(
    sim: &mut Simulation,
    garment: &Garment,
    layout: &Layout,
    warnings: &mut Vec<String>,
) -> Result<()> {
    let (levels, any) = painted(garment, layout, maps::COLLISION_LEVEL, 0.0, warnings)?;
    if any {
        sim.set_particle_levels(&levels.iter().map(|&l| l as i32).collect::<Vec<_>>())?;
    }
    Ok(())
}

/// Fabric per piece and the painted mass and bend scales: per-triangle stretch, shear and
/// bending (the piece's bend times the mean of its vertices' bend scales), per-particle mass
/// scale (the piece's density over the first piece's, times the painted mass scale). Applied
/// whatever the values, so a live edit back to one fabric undoes the last; a garment of one
/// fabric and no painted scales solves exactly as built (the per-element values are computed
/// as the build computes them).
pub fn apply_fabric(
    sim: &mut Simulation,
    garment: &Garment,
    layout: &Layout,
    warnings: &mut Vec<String>,
) -> Result<()> {
    let setup = &garment.setup;
    let base = setup.base_fabric();
    let fabrics: Vec<Fabric> =
        if setup.fabrics.is_empty() { vec![base; layout.vertices.len()] } else { setup.fabrics.clone() };
    let per_tri = |value: fn(&Fabric) -> f32| -> Vec<f32> {
        fabrics.iter().zip(&layout.triangles).flat_map(|(f, &n)| std::iter::repeat_n(value(f), n)).collect()
    };
    // An anisotropic piece's fabric lies along its grain line (the pattern file's), the
    // lengthwise direction on `v` (see `fabric_grain`); an isotropic one keeps the pattern's axes.
    let grain: Vec<f32> = fabrics
        .iter()
        .zip(&garment.pieces)
        .zip(&layout.triangles)
        .flat_map(|((f, p), &n)| std::iter::repeat_n(if f.is_isotropic() { 0.0 } else { fabric_grain(&p.source) }, n))
        .collect();
    sim.set_triangle_grain(&grain)?;
    sim.set_triangle_stiffness_uv(
        &per_tri(|f| f.stretch_uv()[0]),
        &per_tri(|f| f.stretch_uv()[1]),
        &per_tri(|f| f.shear),
    )?;
    let (bend_scale, _) = painted(garment, layout, maps::BEND_SCALE, 1.0, warnings)?;
    let tris = sim.model().mesh.triangles().to_vec();
    let scale =
        |t: &[u32; 3]| (bend_scale[t[0] as usize] + bend_scale[t[1] as usize] + bend_scale[t[2] as usize]) / 3.0;
    if fabrics.iter().all(Fabric::is_isotropic) {
        let bend: Vec<f32> = per_tri(|f| f.bend).into_iter().zip(&tris).map(|(b, t)| b * scale(t)).collect();
        sim.set_triangle_bending(&bend)?;
    } else {
        // Each triangle's three directions, scaled alike by the painted map.
        let bend: Vec<[f32; 3]> = fabrics
            .iter()
            .zip(&layout.triangles)
            .flat_map(|(f, &n)| std::iter::repeat_n(f.bend_directions(), n))
            .zip(&tris)
            .map(|(b, t)| b.map(|b| b * scale(t)))
            .collect();
        sim.set_triangle_bending_directional(&bend)?;
    }
    let (mass, _) = painted(garment, layout, maps::MASS_SCALE, 1.0, warnings)?;
    let scale: Vec<f32> = fabrics
        .iter()
        .zip(&layout.vertices)
        .flat_map(|(f, &n)| std::iter::repeat_n(f.density / base.density, n))
        .zip(&mass)
        .map(|(d, m)| d * m)
        .collect();
    sim.set_mass_scale(&scale)
}

/// The angle of an anisotropic fabric's `u` axis from a piece's pattern x axis, radians: the
/// piece's grain line (the lengthwise grain a pattern file marks) on the fabric's `v` axis, so
/// `u` a quarter turn before it; 0 (the pattern's axes) for a piece without one. Why `v`: the
/// library's source names its axes `u` and `v` only, and every knit and the stretch denim there
/// is stiffer along `v`, as wales and warp, the lengthwise directions, are; a pattern drawn
/// upright (GarmentCode's, most DXF pieces: a vertical grain line) then has `v` up either way.
pub fn fabric_grain(piece: &crate::pattern::Piece) -> f32 {
    match piece.grain {
        Some([a, b]) if (b[0] - a[0]).hypot(b[1] - a[1]) > 0.0 => {
            let lengthwise = (b[1] - a[1]).atan2(b[0] - a[0]);
            // v along the grain line: u a quarter turn clockwise of it; a vertical line gives 0.
            let u = lengthwise - std::f64::consts::FRAC_PI_2;
            // Folded into (−90°, 90°]: a half turn changes nothing.
            let folded = u - std::f64::consts::PI * (u / std::f64::consts::PI).round();
            if folded.abs() < 1e-9 {
                0.0
            } else {
                folded as f32
            }
        }
        _ => 0.0,
    }
}
