//! `tailor._tailor`: the thin Python layer over `tailor-core`.
//!
//! Arrays cross as numpy float32/integer arrays; every solve releases the GIL; every core error
//! becomes one typed Python exception (see [`errors`]). Nothing here holds physics or geometry
//! logic: each function converts its arguments, calls the core, and converts the result.

mod arrange;
mod background;
mod colliders;
mod contour;
mod convert;
mod errors;
mod fabrics;
mod files;
mod garment;
mod io;
mod patterns;
mod scenes;
mod seams;
mod settings;
mod setup;
mod simulation;
mod weld;

use pyo3::prelude::*;

#[pymodule]
fn _tailor(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // One default for every path that sews (Simulation.add_seam, garments, the add-on).
    m.add("MESHER_VERSION", tailor_core::triangulate::MESHER_VERSION)?;
    m.add("DEFAULT_SEAM_STIFFNESS", tailor_core::garment::DEFAULT_SEAM_STIFFNESS)?;
    // The garment setup's defaults, written once in the core (garment_file::setup): the
    // add-on's panel, the command line and the docs read them from here.
    {
        use tailor_core::garment_file::setup as s;
        m.add("DEFAULT_SEAM_BEND_STIFFNESS", s::DEFAULT_SEAM_BEND_STIFFNESS)?;
        m.add("DEFAULT_THICKNESS", s::DEFAULT_THICKNESS)?;
        m.add("DEFAULT_PIN_STIFFNESS", s::DEFAULT_PIN_STIFFNESS)?;
        m.add("DEFAULT_FRICTION", (s::DEFAULT_FRICTION.static_friction, s::DEFAULT_FRICTION.kinetic_friction))?;
        m.add("PAINTED_MAPS", s::maps::ALL.to_vec())?;
        m.add("DEFAULT_SETUP", setup::to_dict(m.py(), &s::GarmentSetup::default())?)?;
    }
    errors::register(m)?;
    m.add_class::<settings::Fabric>()?;
    fabrics::register(m)?;
    m.add_class::<settings::Settings>()?;
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<background::Pending>()?;
    m.add_function(wrap_pyfunction!(scenes::sewn_tube, m)?)?;
    m.add_class::<io::AnimatedMesh>()?;
    m.add_class::<io::Pc2Stream>()?;
    m.add_function(wrap_pyfunction!(io::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(io::read_pc2, m)?)?;
    m.add_function(wrap_pyfunction!(io::write_pc2, m)?)?;
    m.add_function(wrap_pyfunction!(io::write_obj, m)?)?;
    m.add_function(wrap_pyfunction!(colliders::penetration, m)?)?;
    m.add_function(wrap_pyfunction!(colliders::count_self_intersections, m)?)?;
    m.add_function(wrap_pyfunction!(colliders::self_intersecting_pairs, m)?)?;
    m.add_function(wrap_pyfunction!(colliders::edge_strain, m)?)?;
    m.add_function(wrap_pyfunction!(colliders::kinetic_energy, m)?)?;
    m.add_function(wrap_pyfunction!(colliders::max_seam_gap, m)?)?;
    m.add_function(wrap_pyfunction!(colliders::judge, m)?)?;
    m.add_function(wrap_pyfunction!(colliders::judge_unfinished, m)?)?;
    m.add("VERDICT_THRESHOLDS", colliders::verdict_thresholds(m.py())?)?;
    patterns::register(m)?;
    contour::register(m)?;
    m.add_class::<seams::Seam>()?;
    garment::register(m)?;
    arrange::register(m)?;
    weld::register(m)?;
    files::register(m)?;
    Ok(())
}
