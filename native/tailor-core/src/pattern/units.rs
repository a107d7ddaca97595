//! Length units of pattern files and their conversion to metres.
//!
//! Every reader converts to metres as early as possible so that nothing downstream has to
//! know what the file used.

use serde::{Deserialize, Serialize};

/// A length unit a pattern file can be written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Units {
    Millimetres,
    Centimetres,
    Metres,
    Inches,
    Feet,
    /// CSS pixels, 1/96 inch (SVG).
    Pixels,
    /// Typographic points, 1/72 inch (SVG).
    Points,
}

impl Units {
    /// How many metres one unit is.
    pub fn metres(self) -> f64 {
        match self {
            Units::Millimetres => 0.001,
            Units::Centimetres => 0.01,
            Units::Metres => 1.0,
            Units::Inches => 0.0254,
            Units::Feet => 0.3048,
            Units::Pixels => 0.0254 / 96.0,
            Units::Points => 0.0254 / 72.0,
        }
    }

    /// The DXF `$INSUNITS` code, if it names a length unit Tailor knows (0 = unitless is `None`).
    pub fn from_insunits(code: i64) -> Option<Units> {
        match code {
            1 => Some(Units::Inches),
            2 => Some(Units::Feet),
            4 => Some(Units::Millimetres),
            5 => Some(Units::Centimetres),
            6 => Some(Units::Metres),
            _ => None,
        }
    }

    /// Parses a unit name as users and files spell it (`mm`, `cm`, `inch`, `ENGLISH`, `METRIC`).
    /// AAMA's `ENGLISH` means inches and `METRIC` millimetres (AccuMark's metric export unit).
    pub fn parse(name: &str) -> Option<Units> {
        match name.trim().to_ascii_lowercase().as_str() {
            "mm" | "millimetre" | "millimetres" | "millimeter" | "millimeters" | "metric" => Some(Units::Millimetres),
            "cm" | "centimetre" | "centimetres" | "centimeter" | "centimeters" => Some(Units::Centimetres),
            "m" | "metre" | "metres" | "meter" | "meters" => Some(Units::Metres),
            "in" | "inch" | "inches" | "english" => Some(Units::Inches),
            "ft" | "foot" | "feet" => Some(Units::Feet),
            "px" | "pixel" | "pixels" => Some(Units::Pixels),
            "pt" | "point" | "points" => Some(Units::Points),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aama_names_and_insunits() {
        assert_eq!(Units::parse(" ENGLISH "), Some(Units::Inches));
        assert_eq!(Units::parse("METRIC"), Some(Units::Millimetres));
        assert_eq!(Units::from_insunits(4), Some(Units::Millimetres));
        assert_eq!(Units::from_insunits(0), None);
        assert!((Units::Pixels.metres() * 96.0 - 0.0254).abs() < 1e-15);
    }
}
