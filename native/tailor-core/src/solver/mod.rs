//! The cloth solver (filled in by the solver work of issue 2).
