//! The one table of the columns of `curve.csv`: name, unit, meaning and
//! how each is read from a [`CurveRow`]. The CSV header
//! ([`curve_header`]), each CSV line ([`CurveRow::csv`]), the columns of
//! [`crate::Curve`] (which the Python package returns as a dict of numpy
//! arrays) and the column table of `docs/outputs.md`
//! ([`markdown_table`]) all derive from [`CURVE_COLUMNS`]; a new column
//! is one new line here, appended at the end (readers find columns by
//! name, and `junta run --restart` reads shorter rows of older runs).

use crate::post::curve::{Curve, CurveRow};

/// The value of one cell, as `curve.csv` writes it.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// A count or an index, written as an integer.
    Count(usize),
    /// A signed flag (`load_increment_sign`), written as an integer.
    Sign(i8),
    /// A real number, written in `{:e}` form.
    Real(f64),
    /// A real number or an empty cell (`None`).
    MaybeReal(Option<f64>),
    /// A count or an empty cell (`None`).
    MaybeCount(Option<usize>),
    /// Text (`control`).
    Text(String),
}

impl Cell {
    /// The cell as written in `curve.csv`.
    pub fn csv(&self) -> String {
        match self {
            Cell::Count(n) => n.to_string(),
            Cell::Sign(s) => s.to_string(),
            Cell::Real(x) => format!("{x:e}"),
            Cell::MaybeReal(x) => x.map(|x| format!("{x:e}")).unwrap_or_default(),
            Cell::MaybeCount(n) => n.map(|n| n.to_string()).unwrap_or_default(),
            Cell::Text(t) => t.clone(),
        }
    }

    /// The cell as a number (an empty cell is NaN), or `None` for text.
    pub fn number(&self) -> Option<f64> {
        match self {
            Cell::Count(n) => Some(*n as f64),
            Cell::Sign(s) => Some(*s as f64),
            Cell::Real(x) => Some(*x),
            Cell::MaybeReal(x) => Some(x.unwrap_or(f64::NAN)),
            Cell::MaybeCount(n) => Some(n.map_or(f64::NAN, |n| n as f64)),
            Cell::Text(_) => None,
        }
    }
}

/// One column of `curve.csv`.
#[derive(Clone, Copy)]
pub struct CurveColumn {
    /// Name in the header.
    pub name: &'static str,
    /// Unit, in the model's units (`-`: a number without unit).
    pub unit: &'static str,
    /// What it holds.
    pub meaning: &'static str,
    /// Its value on a row.
    pub value: fn(&CurveRow) -> Cell,
}

impl std::fmt::Debug for CurveColumn {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CurveColumn")
            .field("name", &self.name)
            .field("unit", &self.unit)
            .finish()
    }
}

/// The columns of `curve.csv`, in order.
pub const CURVE_COLUMNS: &[CurveColumn] = &[
    CurveColumn {
        name: "increment",
        unit: "-",
        meaning: "converged increment, 1-based, counted across restarts",
        value: |r| Cell::Count(r.increment),
    },
    CurveColumn {
        name: "step",
        unit: "-",
        meaning: "step of the load program, 0-based",
        value: |r| Cell::Count(r.step),
    },
    CurveColumn {
        name: "load_factor",
        unit: "-",
        meaning: "load factor reached",
        value: |r| Cell::Real(r.lambda),
    },
    CurveColumn {
        name: "reaction",
        unit: "force",
        meaning: "total force of the curve's reaction set in its component (the load factor with `conjugate`); with equations (`*EQUATION`, `[[tie]]`) the generalized reaction, so a node that drives a tied face reports the face's force (`summary.json` `generalized_reactions`); empty without a curve",
        value: |r| Cell::MaybeReal(r.reaction),
    },
    CurveColumn {
        name: "displacement",
        unit: "length",
        meaning: "mean displacement of the curve's point set in its component (`f_ext . u` with `conjugate`); empty without a curve",
        value: |r| Cell::MaybeReal(r.displacement),
    },
    CurveColumn {
        name: "failed_points",
        unit: "-",
        meaning: "interface integration points that have failed",
        value: |r| Cell::Count(r.failed),
    },
    CurveColumn {
        name: "interface_points",
        unit: "-",
        meaning: "interface integration points of the model",
        value: |r| Cell::Count(r.points),
    },
    CurveColumn {
        name: "newton_iterations",
        unit: "-",
        meaning: "Newton iterations of the converged attempt",
        value: |r| Cell::Count(r.iterations),
    },
    CurveColumn {
        name: "cutbacks",
        unit: "-",
        meaning: "cut-backs before the increment converged",
        value: |r| Cell::Count(r.cutbacks),
    },
    CurveColumn {
        name: "seconds",
        unit: "s",
        meaning: "wall-clock time of the increment, failed attempts included",
        value: |r| Cell::Real(r.seconds),
    },
    CurveColumn {
        name: "small_increment",
        unit: "-",
        meaning: "1 when the paper's small-increment rule sized the increment, else 0",
        value: |r| Cell::Count(r.small as usize),
    },
    CurveColumn {
        name: "dissipated_energy",
        unit: "energy",
        meaning: "fracture energy dissipated in all interfaces so far",
        value: |r| Cell::Real(r.dissipated),
    },
    CurveColumn {
        name: "damaged_area",
        unit: "area",
        meaning: "area of the failed interface points",
        value: |r| Cell::Real(r.damaged_area),
    },
    CurveColumn {
        name: "negative_pivots",
        unit: "-",
        meaning: "negative pivots of the last factorised tangent (`ldlt`); empty when the back end does not know",
        value: |r| Cell::MaybeCount(r.negative_pivots),
    },
    CurveColumn {
        name: "load_increment_sign",
        unit: "-",
        meaning: "sign of the load-factor increment: 1, -1 or 0",
        value: |r| Cell::Sign(r.load_sign),
    },
    CurveColumn {
        name: "control",
        unit: "-",
        meaning: "what constrained the increment: `load`, `arc` or `dissipation`",
        value: |r| Cell::Text(r.control.clone()),
    },
    CurveColumn {
        name: "conjugate_displacement",
        unit: "length",
        meaning: "`f_ext . u`, the displacement work-conjugate to the load factor",
        value: |r| Cell::Real(r.conjugate),
    },
    CurveColumn {
        name: "frictional_dissipation",
        unit: "energy",
        meaning: "energy dissipated by friction and interface plasticity so far",
        value: |r| Cell::Real(r.frictional),
    },
    CurveColumn {
        name: "temperature_factor",
        unit: "-",
        meaning: "fraction of the model's temperature change applied (1 without a temperature program)",
        value: |r| Cell::Real(r.temperature_factor),
    },
    CurveColumn {
        name: "viscous_energy",
        unit: "energy",
        meaning: "energy dissipated by the laws' viscous regularisation so far",
        value: |r| Cell::Real(r.viscous),
    },
    CurveColumn {
        name: "external_work",
        unit: "energy",
        meaning: "work of the reactions of the prescribed dofs and of the applied loads so far (trapezoid rule)",
        value: |r| Cell::Real(r.external_work),
    },
    CurveColumn {
        name: "crack_length",
        unit: "length",
        meaning: "damaged area over the crack width; empty without damage",
        value: |r| Cell::MaybeReal(r.crack_length),
    },
    CurveColumn {
        name: "crack_front",
        unit: "length",
        meaning: "largest coordinate of a failed point along the crack direction; empty before the first",
        value: |r| Cell::MaybeReal(r.crack_front),
    },
    CurveColumn {
        name: "process_zone_length",
        unit: "length",
        meaning: "extent of the process zone ahead of the front along the crack direction",
        value: |r| Cell::MaybeReal(r.process_zone_length),
    },
    CurveColumn {
        name: "process_zone_points",
        unit: "-",
        meaning: "process-zone points along the crack direction",
        value: |r| Cell::MaybeCount(r.process_zone_points),
    },
    CurveColumn {
        name: "cycles",
        unit: "cycles",
        meaning: "load cycles reached (0 outside a fatigue program)",
        value: |r| Cell::Real(r.cycles),
    },
    CurveColumn {
        name: "energy_release_rate",
        unit: "energy/area",
        meaning: "J integral of the cohesive tractions (fatigue programs that measure it)",
        value: |r| Cell::MaybeReal(r.energy_release_rate),
    },
    CurveColumn {
        name: "crack_mode_ratio",
        unit: "-",
        meaning: "mode ratio `G_II / G` of that J integral",
        value: |r| Cell::MaybeReal(r.crack_mode_ratio),
    },
    CurveColumn {
        name: "crack_growth_rate",
        unit: "length/cycle",
        meaning: "crack growth per cycle `da/dN` on the rows of a fatigue step where the crack grew",
        value: |r| Cell::MaybeReal(r.crack_growth_rate),
    },
];

/// The header line of `curve.csv` (with its newline).
pub fn curve_header() -> String {
    let names: Vec<&str> = CURVE_COLUMNS.iter().map(|c| c.name).collect();
    format!("{}\n", names.join(","))
}

/// The table of the columns as `docs/outputs.md` shows it (Markdown,
/// with its header rows).
pub fn markdown_table() -> String {
    let mut s = String::from("| column | unit | meaning |\n|---|---|---|\n");
    for c in CURVE_COLUMNS {
        s.push_str(&format!("| `{}` | {} | {} |\n", c.name, c.unit, c.meaning));
    }
    s
}

impl CurveRow {
    /// The row as a line of `curve.csv` (with its newline): the cells of
    /// [`CURVE_COLUMNS`] in order, floats in `{:e}` form, `None` as an
    /// empty field.
    pub fn csv(&self) -> String {
        let cells: Vec<String> = CURVE_COLUMNS
            .iter()
            .map(|c| (c.value)(self).csv())
            .collect();
        format!("{}\n", cells.join(","))
    }
}

impl Curve {
    /// The columns of `rows` ([`CURVE_COLUMNS`], `control` apart).
    pub fn from_rows(rows: &[CurveRow]) -> Curve {
        let columns = CURVE_COLUMNS
            .iter()
            .filter(|c| c.name != "control")
            .map(|c| {
                let values = rows
                    .iter()
                    .map(|r| (c.value)(r).number().unwrap_or(f64::NAN))
                    .collect();
                (c.name.to_string(), values)
            })
            .collect();
        Curve {
            columns,
            control: rows.iter().map(|r| r.control.clone()).collect(),
        }
    }
}
