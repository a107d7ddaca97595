//! The fabric library: named fabrics from published measurements, and the one rule that turns
//! a measured fabric into the solver's [`Fabric`].
//!
//! # Source
//!
//! Every entry is one of the ten cloth samples measured by Huamin Wang, Ravi Ramamoorthi and
//! James F. O'Brien, "Data-Driven Elastic Models for Cloth: Modeling and Measurement", ACM
//! Transactions on Graphics 30(4):71, 2011 (SIGGRAPH 2011), doi:10.1145/2010324.1964966: each
//! sample's stretching and bending, measured on a setup of their own and fitted to a piecewise
//! linear, anisotropic model, published as the material files of their simulator ARCSim
//! (`materials/NAME.json`: `density` in kg/m², `stretching` as six rows of `[k₀, k₁, k₂, k₃]`,
//! `bending` as three rows of five samples). Each entry of [`LIBRARY`] holds the file's numbers
//! the rules below use (four of the six stretching rows, the first sample of each bending row)
//! as they are printed there; the properties are computed from them by the rules, once, in code.
//! The files come with ARCSim and the Berkeley Garment Library; their README asks that any
//! scholarly publication using the data cite the paper above, and states no other terms for it.
//!
//! # From ARCSim's model to a measured property
//!
//! * **Stretch.** ARCSim's membrane energy is `A/2·(k₀G₀₀² + 2k₁G₀₀G₁₁ + k₂G₁₁² + k₃G₀₁²)` in the
//!   Green strain `G`, with `k = 2·(row 0 + s·(row(direction) − row 0))`, `s = 6·(λ − 1)` the
//!   principal stretch's share of the way to 7/6 (`dde.cpp`, `evaluate_stretching_sample`).
//!   A fabric is quoted at **5 % strain** (`s = 0.3`), the range a woven garment works in: the
//!   uniaxial stiffness along `u` is `k₀` from the 0° row, along `v` `k₂` from the 90° row (N/m;
//!   a knit's row 0 is nearly slack and stiffens by row 1, so the strain chosen matters most there).
//! * **Shear.** The `k₃` term is `A/2·(k₃/4)·γ²` for a shear angle `γ` (`G₀₁ ≈ γ/2`), pure shear's
//!   principal directions lie at 45°: `shear = k₃/2` from the 45° row at the same 5 %, in the
//!   convention of the solver's shear (whose energy is `A/2·(shear/2)·γ²`).
//! * **Bending.** ARCSim's hinge energy is `ke·l²/(2a)·θ²/4` (`physics.cpp`, `bending_energy`;
//!   `a` the two triangles' area, `θ` the dihedral angle). On a mesh bent onto a cylinder its
//!   sum is **0.25** of the continuum `½·B·κ²·A` with `B = ke` (measured on our meshes away from
//!   the border: 0.2512 at 5 mm edges, 0.2526 at 1 cm; `tests/test_fabric_library.py`), so the
//!   measured flexural rigidity is `B = ke/4` (N·m), in the warp-like `u`, bias and `v`
//!   directions.
//!
//! # Into the solver
//!
//! The solver's fabric keeps the source's directions ([`Fabric`], `u` along the pattern's x
//! axis): `stretch` along `u`, `stretch_v` along `v`, `shear` as measured, and the bending of
//! hinges whose edge runs along `u`, on the bias and along `v` (`bend`, `bend_bias`, `bend_v`,
//! as ARCSim indexes its bending rows by the edge's direction). The quadratic hinge model's
//! energy (`constraints/bending.rs`, `3k/(A₀+A₁)·½‖ΣKᵢxᵢ‖²`) is **3 times** the continuum
//! `½·B·κ²·A` of `B = k` (measured the same way,
//! [`tests::the_hinge_energy_is_three_times_the_continuum_one`]), so a rigidity `B` enters as
//! `bend = B / 3` ([`HINGE_ENERGY_PER_RIGIDITY`]). [`MeasuredFabric::isotropic_fabric`] gives
//! the geometric means in every direction (the library's solver fabric before anisotropy).
//!
//! What the library does not hold: silk, chiffon and leather (no measured source in the
//! repository yet); the sources' nonlinear stiffening beyond 5 % strain and with curvature.

use crate::error::{Result, TailorError};
use crate::solver::Fabric;

/// The quadratic hinge model's bending energy over the continuum energy `½·B·κ²·A` of a
/// rigidity `B` equal to its parameter: a measured rigidity enters the solver divided by it.
pub const HINGE_ENERGY_PER_RIGIDITY: f64 = 3.0;

/// The share of the strain range of ARCSim's two stiffness levels a fabric is quoted at: 5 %
/// strain of the 1/6 between them.
pub const QUOTED_STRAIN: f64 = 0.05;

/// ARCSim's bending energy over the continuum energy `½·B·κ²·A` of a rigidity `B` equal to its
/// `ke` (the module's "From ARCSim's model"): a measured `ke` is a rigidity of `ke/4`.
pub const ARCSIM_HINGE_ENERGY_PER_RIGIDITY: f64 = 0.25;

/// One measured fabric, as its source gives it (ARCSim's material file; SI units: kg/m², N/m,
/// N·m), with the properties the module's rules derive from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredFabric {
    /// The source's sample name (its material file's).
    pub name: &'static str,
    /// What the source says it is for, and its fibres.
    pub description: &'static str,
    /// Area density, kg/m².
    pub density: f64,
    /// The stretching rows `[k₀, k₁, k₂, k₃]`: unstrained (the file's row 0), and at the second
    /// strain level with the principal stretch at 0°, 45° and 90° (rows 1, 3 and 5).
    pub stretch_rest: [f64; 4],
    pub stretch_0: [f64; 4],
    pub stretch_45: [f64; 4],
    pub stretch_90: [f64; 4],
    /// The first (lowest curvature) bending sample of the rows at 0°, 45° and 90°: ARCSim's `ke`.
    pub bending_ke: [f64; 3],
}

impl MeasuredFabric {
    /// ARCSim's stiffness component `c` at [`QUOTED_STRAIN`] in the direction of `row` (its
    /// interpolation from the unstrained row, doubled as `evaluate_stretching_sample` does;
    /// negative stiffness clamped to 0 as there).
    fn at_quoted_strain(&self, row: &[f64; 4], c: usize) -> f64 {
        let s = QUOTED_STRAIN * 6.0;
        2.0 * (self.stretch_rest[c] + s * (row[c] - self.stretch_rest[c])).max(0.0)
    }

    /// Uniaxial stretch stiffness along the source's `u` axis at 5 % strain, N/m.
    pub fn stretch_u(&self) -> f64 {
        self.at_quoted_strain(&self.stretch_0, 0)
    }

    /// Uniaxial stretch stiffness along `v` at 5 % strain, N/m.
    pub fn stretch_v(&self) -> f64 {
        self.at_quoted_strain(&self.stretch_90, 2)
    }

    /// Shear stiffness at 5 % strain in the solver's convention (`k₃/2` of the 45° row), N/m.
    pub fn shear(&self) -> f64 {
        0.5 * self.at_quoted_strain(&self.stretch_45, 3)
    }

    /// Flexural rigidity bending about `u`, the bias and `v`, N·m.
    pub fn rigidities(&self) -> [f64; 3] {
        self.bending_ke.map(|ke| ke * ARCSIM_HINGE_ENERGY_PER_RIGIDITY)
    }

    /// The isotropic flexural rigidity the solver's fabric stands for: the geometric mean of
    /// the three directions, N·m.
    pub fn rigidity(&self) -> f64 {
        let [u, b, v] = self.rigidities();
        (u * b * v).cbrt()
    }

    /// The solver's fabric for this measured one, anisotropic as measured (see the module: the
    /// source's `u` and `v`, and the hinge model's factor).
    pub fn fabric(&self) -> Fabric {
        let [u, b, v] = self.rigidities().map(|r| (r / HINGE_ENERGY_PER_RIGIDITY) as f32);
        Fabric {
            density: self.density as f32,
            stretch: self.stretch_u() as f32,
            shear: self.shear() as f32,
            bend: u,
            stretch_v: Some(self.stretch_v() as f32),
            bend_bias: Some(b),
            bend_v: Some(v),
        }
    }

    /// The isotropic fabric of the geometric means: `stretch` of the two directions, `bend` of
    /// the three rigidities (for comparisons with the anisotropic [`fabric`](Self::fabric)).
    pub fn isotropic_fabric(&self) -> Fabric {
        Fabric::isotropic(
            self.density as f32,
            (self.stretch_u() * self.stretch_v()).sqrt() as f32,
            self.shear() as f32,
            (self.rigidity() / HINGE_ENERGY_PER_RIGIDITY) as f32,
        )
    }
}

/// The library, lightest to heaviest, each entry the source's numbers for one sample.
pub const LIBRARY: &[MeasuredFabric] = &[
    MeasuredFabric {
        name: "tango-red-jet-set",
        description: "jacket; 100 % polyester, light woven",
        density: 0.113,
        stretch_rest: [43.067627, 54.373299, 171.424835, 14.3147],
        stretch_0: [75.151695, 82.195221, 236.163773, -7.230383],
        stretch_45: [107.244377, 124.801788, 364.583557, 41.386868],
        stretch_90: [227.028687, -21.865427, 404.867188, 62.636021],
        bending_ke: [14.293814e-6, 21.9517e-6, 20.345654e-6],
    },
    MeasuredFabric {
        name: "white-dots-on-blk",
        description: "tablecloth; 100 % polyester, plain woven",
        density: 0.128,
        stretch_rest: [2002.08618, 0.345588, 2027.48559, 19.189022],
        stretch_0: [2107.22753, 36.371597, 2171.73339, 16.904713],
        stretch_45: [2107.73291, 28.389059, 2132.72607, 101.462021],
        stretch_90: [2107.30786, 61.21629, 2150.4768, 37.668823],
        bending_ke: [51.713814e-6, 40.65947e-6, 31.282822e-6],
    },
    MeasuredFabric {
        name: "gray-interlock",
        description: "t-shirt; 60 % cotton 40 % polyester, interlock knit",
        density: 0.187,
        stretch_rest: [16.593832, -14.69599, 34.477123, 36.860302],
        stretch_0: [46.364765, 53.694656, 261.013855, -29.691301],
        stretch_45: [123.98922, 105.18177, 365.966217, 44.217571],
        stretch_90: [127.44381, 85.848587, 405.872833, 32.238411],
        bending_ke: [23.191698e-6, 24.749964e-6, 14.267624e-6],
    },
    MeasuredFabric {
        name: "white-swim-solid",
        description: "swimsuit; 87 % nylon 13 % spandex, knit",
        density: 0.204,
        stretch_rest: [47.971176, 6.834521, 104.615456, 60.773663],
        stretch_0: [40.369045, 23.092957, 169.66629, -24.68189],
        stretch_45: [51.393467, -32.966949, 79.881721, 35.973194],
        stretch_90: [68.621185, 40.13195, 124.468513, 36.199604],
        bending_ke: [60.237942e-6, 58.803211e-6, 51.018833e-6],
    },
    MeasuredFabric {
        name: "royal-target",
        description: "pants; 65 % cotton 35 % polyester, twill woven",
        density: 0.22,
        stretch_rest: [2016.55456, 9.170511, 2034.97644, 104.759674],
        stretch_0: [2109.51684, 38.604588, 2173.93969, 19.129177],
        stretch_45: [2110.33349, 30.987429, 2135.0791, 121.482445],
        stretch_90: [2109.52612, 63.424015, 2152.73852, 39.885654],
        bending_ke: [125.409805e-6, 107.997696e-6, 125.409805e-6],
    },
    MeasuredFabric {
        name: "navy-sparkle-sweat",
        description: "sweater; 96 % polyester 4 % spandex, sweatshirt knit",
        density: 0.224,
        stretch_rest: [12.486332, -19.875324, 3.272434, 17.616289],
        stretch_0: [32.172089, 56.01276, 283.46637, -2.438436],
        stretch_45: [77.093796, 2.958664, 91.25116, 6.1077],
        stretch_90: [92.34317, 117.527084, 243.264908, 47.338436],
        bending_ke: [59.469658e-6, 40.072277e-6, 45.625023e-6],
    },
    MeasuredFabric {
        name: "pink-ribbon-brown",
        description: "blanket; 100 % polyester, fleece",
        density: 0.228,
        stretch_rest: [151.503906, 106.02816, 244.830673, 30.250183],
        stretch_0: [164.124344, 33.689709, 268.195221, 30.074625],
        stretch_45: [209.604172, 175.223465, 220.19812, 129.643188],
        stretch_90: [96.805817, 54.626881, 359.792633, 30.340616],
        bending_ke: [117.070122e-6, 87.509773e-6, 59.774277e-6],
    },
    MeasuredFabric {
        name: "ivory-rib-knit",
        description: "underwear; 95 % cotton 5 % spandex, rib knit",
        density: 0.276,
        stretch_rest: [42.871021, -0.234556, 65.166023, 83.175644],
        stretch_0: [52.422512, 7.219094, 245.337158, -31.129513],
        stretch_45: [91.209549, 4.940307, 109.746452, 27.60943],
        stretch_90: [105.649139, 0.416488, 254.593491, 3.472504],
        bending_ke: [46.237591e-6, 30.01593e-6, 32.243889e-6],
    },
    MeasuredFabric {
        name: "camel-ponte-roma",
        description: "jacket; 60 % polyester 40 % rayon, ponte knit",
        density: 0.284,
        stretch_rest: [31.146198, -12.802702, 44.028667, 31.896357],
        stretch_0: [78.707756, 26.754574, 268.680725, 27.743423],
        stretch_45: [113.367035, 54.802021, 175.126572, 44.65733],
        stretch_90: [143.933365, 49.654823, 191.777588, 39.491055],
        bending_ke: [36.348366e-6, 33.013252e-6, 37.157593e-6],
    },
    MeasuredFabric {
        name: "11oz-black-denim",
        description: "jeans; 99 % cotton 1 % spandex, 11 oz denim",
        density: 0.324,
        stretch_rest: [205.352005, 10.234077, 1013.88629, 53.387184],
        stretch_0: [232.027634, 40.646339, 1052.84289, 64.980499],
        stretch_45: [225.95105, 62.095657, 1059.59741, 83.99202],
        stretch_90: [225.767487, 40.917892, 1051.55712, 71.810631],
        bending_ke: [64.196457e-6, 73.384567e-6, 96.951576e-6],
    },
];

/// The measured fabric called `name` (a name of [`LIBRARY`]); an error naming the known ones
/// otherwise.
pub fn named(name: &str) -> Result<&'static MeasuredFabric> {
    LIBRARY.iter().find(|f| f.name == name).ok_or_else(|| {
        let known: Vec<&str> = LIBRARY.iter().map(|f| f.name).collect();
        TailorError::setting("fabric", name, format!("not in the fabric library (known: {})", known.join(", ")))
    })
}

/// Reads a garment setup's `fabrics`: each entry the solver's four values (an object with
/// `density`, `stretch`, `shear`, `bend`) or a library fabric's name (a string, resolved by
/// [`named`] and [`MeasuredFabric::fabric`]). Written back, every entry is the four values.
pub fn deserialize_entries<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Vec<Fabric>, D::Error> {
    struct Entry(Fabric);
    impl<'de> serde::Deserialize<'de> for Entry {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
            struct Visit;
            impl<'de> serde::de::Visitor<'de> for Visit {
                type Value = Entry;
                fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                    f.write_str("a fabric: {density, stretch, shear, bend} or a fabric library name")
                }
                fn visit_str<E: serde::de::Error>(self, name: &str) -> std::result::Result<Entry, E> {
                    named(name).map(|m| Entry(m.fabric())).map_err(|e| E::custom(e.to_string()))
                }
                fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> std::result::Result<Entry, A::Error> {
                    use serde::Deserialize;
                    Fabric::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(Entry)
                }
            }
            d.deserialize_any(Visit)
        }
    }
    let entries: Vec<Entry> = serde::Deserialize::deserialize(d)?;
    Ok(entries.into_iter().map(|e| e.0).collect())
}

#[cfg(test)]
mod tests;
