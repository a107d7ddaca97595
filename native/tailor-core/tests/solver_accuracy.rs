//! Accuracy of a step against the reference solver, and determinism.

use tailor_core::scenes::sewn_tube;
use tailor_core::solver::{Fabric, Method, ReferenceOptions, Simulation, SolverSettings, StepMeasurement};

/// A 0.1 × 0.5 m strip hung from its top edge but placed 10 % too long, so the step must pull
/// it up by millimetres: a stretch-dominated step, far above the f32 floor.
fn stretched_strip() -> Simulation {
    let (w, l, nx, ny) = (0.1f32, 0.5f32, 4usize, 20usize);
    let (rest, tris) = tailor_core::scenes::rectangle(w, l, nx, ny);
    let pos: Vec<[f32; 3]> = rest.iter().map(|r| [r[0], 0.0, 1.1 * (r[1] - l)]).collect();
    let mesh = tailor_core::mesh::ClothMesh::new(pos, rest, tris).unwrap();
    let fabric = Fabric::isotropic(0.2, 200.0, 50.0, 1e-6);
    let mut sim = Simulation::new(mesh, fabric, SolverSettings::default()).unwrap();
    let top: Vec<u32> = (0..=nx).map(|i| (ny * (nx + 1) + i) as u32).collect();
    sim.pin(&top, None).unwrap();
    sim
}

fn first_below(m: &StepMeasurement, tol: f64) -> Option<u32> {
    m.records.iter().find(|r| r.measures.distance_rel < tol).map(|r| r.iteration)
}

#[test]
fn chebyshev_reaches_1e3_in_fewer_iterations_than_gauss_seidel() {
    let mut sim = stretched_strip();
    let before = sim.state_hash();
    let opts = ReferenceOptions::default();
    let gs = sim.measure_step(1.0 / 30.0, Method::GaussSeidel, 3000, opts).unwrap();
    let ch = sim.measure_step(1.0 / 30.0, Method::Chebyshev, 400, opts).unwrap();
    assert_eq!(sim.state_hash(), before, "measuring must not change the simulation");
    println!("reference: {:?}", gs.reference);
    assert!(gs.reference.last_change < 1e-6, "reference not converged: {:?}", gs.reference);
    for k in [0usize, 9, 49, 99, 199, 399] {
        let (a, b) = (gs.records[k].measures, ch.records[k].measures);
        println!(
            "it {:3}: GS dist {:.2e} obj {:.2e} res {:.2e} | Cheb dist {:.2e} obj {:.2e} res {:.2e}",
            k + 1,
            a.distance_rel,
            a.objective_rel,
            a.residual_rel,
            b.distance_rel,
            b.objective_rel,
            b.residual_rel
        );
    }
    let (n_gs, n_ch) = (first_below(&gs, 1e-3), first_below(&ch, 1e-3));
    println!("iterations to 1e-3 relative distance: Gauss-Seidel {n_gs:?}, Chebyshev {n_ch:?}");
    let (n_ch, n_gs) = (n_ch.expect("Chebyshev never reached 1e-3"), n_gs.expect("Gauss-Seidel never reached 1e-3"));
    assert!(n_ch * 2 < n_gs, "Chebyshev {n_ch} vs Gauss-Seidel {n_gs}");
    // The three measures fall together: the last record is far below the first.
    for m in [&gs, &ch] {
        let (a, b) = (m.records.first().unwrap().measures, m.records.last().unwrap().measures);
        assert!(b.objective_rel < 0.1 * a.objective_rel && b.residual_rel < 0.1 * a.residual_rel, "{a:?} -> {b:?}");
        assert!(m.records.windows(2).all(|w| w[1].seconds >= w[0].seconds));
    }
}

#[test]
fn jacobi_converges_but_more_slowly_than_gauss_seidel() {
    let mut sim = stretched_strip();
    let opts = ReferenceOptions::default();
    let j = sim.measure_step(1.0 / 30.0, Method::Jacobi, 100, opts).unwrap();
    let gs = sim.measure_step(1.0 / 30.0, Method::GaussSeidel, 100, opts).unwrap();
    let (ej, egs) = (j.records.last().unwrap().measures.distance_rel, gs.records.last().unwrap().measures.distance_rel);
    println!("after 100 iterations: Jacobi {ej:.2e}, Gauss-Seidel {egs:.2e}");
    assert!(ej < 0.9 && egs < ej);
}

fn run_tube(frames: usize) -> u64 {
    let tube = sewn_tube(0.3, 0.3, 0.03, 0.08, 0.0, 1000.0).unwrap();
    let mut sim = Simulation::new(tube.mesh, Fabric::default(), SolverSettings::default()).unwrap();
    for s in tube.seams {
        sim.add_seam(s).unwrap();
    }
    for _ in 0..frames {
        sim.step(1.0 / 30.0).unwrap();
    }
    sim.state_hash()
}

/// Same inputs, same bits: for a given thread count, and (by construction: colouring and
/// reductions do not depend on scheduling) across thread counts too.
#[test]
fn positions_are_deterministic() {
    let a = run_tube(12);
    let b = run_tube(12);
    assert_eq!(a, b, "two runs differ");
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| run_tube(12));
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap().install(|| run_tube(12));
    assert_eq!(one, two, "1 and 2 threads differ");
    assert_eq!(a, two);
}

/// A solver's own threads (`Solver::set_threads`): its steps run on that many (the statistics
/// say so, whatever the global pool), give the bits of any other thread count, and 0 threads
/// is an error.
#[test]
fn a_solver_runs_on_the_threads_it_is_given() {
    use tailor_core::engine::{Backend, Solver};
    let run = |threads: Option<usize>| {
        let tube = sewn_tube(0.3, 0.3, 0.03, 0.08, 0.0, 1000.0).unwrap();
        let mut sim = Simulation::new(tube.mesh, Fabric::default(), SolverSettings::default()).unwrap();
        for s in tube.seams {
            sim.add_seam(s).unwrap();
        }
        let mut solver = Solver::new(sim, Backend::Cpu);
        solver.set_threads(threads).unwrap();
        let mut used = Vec::new();
        for _ in 0..12 {
            used.push(solver.step(1.0 / 30.0).unwrap().threads);
        }
        (solver.simulation().state_hash(), used, solver.threads())
    };
    let (one, used_one, t1) = run(Some(1));
    let (three, used_three, t3) = run(Some(3));
    let (global, used_global, _) = run(None);
    assert!(used_one.iter().all(|&t| t == 1) && t1 == 1, "{used_one:?}");
    assert!(used_three.iter().all(|&t| t == 3) && t3 == 3, "{used_three:?}");
    assert!(used_global.iter().all(|&t| t == rayon::current_num_threads()), "{used_global:?}");
    assert_eq!(one, three, "1 and 3 threads differ");
    assert_eq!(one, global, "a pool of its own and the global pool differ");
    let tube = sewn_tube(0.3, 0.3, 0.03, 0.08, 0.0, 1000.0).unwrap();
    let sim = Simulation::new(tube.mesh, Fabric::default(), SolverSettings::default()).unwrap();
    let mut solver = Solver::new(sim, Backend::Cpu);
    assert!(solver.set_threads(Some(0)).is_err());
}

/// `measure_methods` runs a method with the two-level step's coarse correction when asked, on
/// the same frozen substep and reference: on the strip whose step pulls it up (a smooth,
/// large-scale error) the corrected Chebyshev run is nearer the reference after as many
/// iterations, and measuring changes nothing (the simulation's own coarse grid, none here,
/// put back).
#[test]
fn the_two_level_run_is_measured_beside_the_plain_one() {
    use tailor_core::solver::MethodRun;
    let mut sim = stretched_strip();
    let before = sim.state_hash();
    let runs = [
        MethodRun { method: Method::Chebyshev, iterations: 60, two_level: false },
        MethodRun { method: Method::Chebyshev, iterations: 60, two_level: true },
    ];
    let m = sim.measure_methods(1.0 / 30.0, &runs, ReferenceOptions::default(), &|_| true).unwrap();
    assert_eq!(sim.state_hash(), before, "measuring must not change the simulation");
    let (plain, two) = (&m.methods[0], &m.methods[1]);
    assert!(!plain.two_level && two.two_level);
    for k in [4usize, 14, 29, 59] {
        println!(
            "it {:2}: plain dist {:.2e} obj {:.2e} | two-level dist {:.2e} obj {:.2e}",
            k + 1,
            plain.records[k].measures.distance_rel,
            plain.records[k].measures.objective_rel,
            two.records[k].measures.distance_rel,
            two.records[k].measures.objective_rel
        );
    }
    let (p, t) = (plain.records[14].measures, two.records[14].measures);
    assert!(t.distance_rel < 0.5 * p.distance_rel, "after 15 iterations: plain {p:?}, two-level {t:?}");
}
