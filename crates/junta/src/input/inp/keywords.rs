//! The keyword table: every keyword the reader understands, what it reads
//! and its notes ([`KEYWORDS`]). The table feeds the parser's dispatch, the
//! list of valid keywords in the error for an unknown one, and the table of
//! `docs/decks.md` (a test checks that they are the same). Also the `** junta:`
//! directives, the keyword loop, `*HEADING` and `*CONTROLS`.

use super::*;

/// Which reader of the parser a keyword goes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Reader {
    Heading,
    Node,
    Element,
    Set,
    Material,
    Elastic,
    Density,
    Expansion,
    InitialConditions,
    Temperature,
    Membrane,
    DamageInitiation,
    DamageEvolution,
    DamageStabilization,
    Orientation,
    SolidSection,
    CohesiveSection,
    Boundary,
    Cload,
    Amplitude,
    Dload,
    Surface,
    Dsload,
    Equation,
    Step,
    Static,
    Controls,
    EndStep,
    Include,
    NodePrint,
    ElPrint,
    /// An output request (`*NODE FILE`, `*OUTPUT`, ...): noted and skipped.
    OutputRequest,
}

/// One row of the keyword table: the keywords (upper case, without `*`)
/// that one reader handles, the parameters it supports and its notes, as
/// `docs/decks.md` shows them (Markdown).
#[derive(Debug)]
pub struct Keyword {
    /// The keywords, e.g. `["NSET", "ELSET"]`.
    pub names: &'static [&'static str],
    /// The parameters and data it reads.
    pub parameters: &'static str,
    /// Notes: what it is checked against, what is noted or refused.
    pub notes: &'static str,
    reader: Reader,
}

/// Every keyword the deck reader understands, in the order of
/// `docs/decks.md`'s table.
pub const KEYWORDS: &[Keyword] = &[
    Keyword {
        names: &["HEADING"],
        parameters: r#""#,
        notes: r#"accepted"#,
        reader: Reader::Heading,
    },
    Keyword {
        names: &["NODE"],
        parameters: r#"`NSET=`"#,
        notes: r#"data lines `label[, x[, y[, z]]]`: a missing coordinate is 0 (2D decks give x and y)"#,
        reader: Reader::Node,
    },
    Keyword {
        names: &["ELEMENT"],
        parameters: r#"`ELSET=`, `TYPE=` C3D6, C3D8, C3D8I, C3D15, C3D20, C3D20R, C3D27, COH3D8, COH3D6; 2D: CPE3, CPE4, CPE4I, CPE6, CPE8, CPE8R, CPS3, CPS4, CPS4I, CPS6, CPS8, CPS8R, CAX3, CAX4, CAX4I, CAX6, CAX8, CAX8R, COH2D4, COHAX4"#,
        notes: r#"2D: CalculiX's own 2D decks against their `.dat.ref` in [`crates/cli/tests/plane_decks.rs`](../crates/cli/tests/plane_decks.rs) (what CalculiX's 3D expansion changes: [2D decks](#2d-decks)). C3D8I: ccx 2.20 on [`crates/cli/tests/data/cantilever_c3d8i.inp`](../crates/cli/tests/data/cantilever_c3d8i.inp) (`c3d8i_cantilever_deck_matches_calculix` in [`crates/cli/tests/cli.rs`](../crates/cli/tests/cli.rs)); C3D6/C3D15: `wedge_cantilever_decks_match_calculix` (same file)"#,
        reader: Reader::Element,
    },
    Keyword {
        names: &["NSET", "ELSET"],
        parameters: r#"`GENERATE`"#,
        notes: r#""#,
        reader: Reader::Set,
    },
    Keyword {
        names: &["MATERIAL"],
        parameters: r#"`NAME=`"#,
        notes: r#"the damage keywords below must be inside one"#,
        reader: Reader::Material,
    },
    Keyword {
        names: &["ELASTIC"],
        parameters: r#"one temperature on the data line is noted (constants used at every temperature); isotropic; `TYPE=ENGINEERING CONSTANTS`; `ORTHO` (nine D_ijkl); `ANISO` (21 D_ijkl, material `anisotropic`); `TYPE=TRACTION` (`K_nn, K_ss, K_tt`, [cohesive decks](#cohesive-decks))"#,
        notes: r#"`elastic_ortho_matches_calculix` ([`crates/cli/tests/data/ortho_cube.inp`](../crates/cli/tests/data/ortho_cube.inp)), `orientation_and_aniso_match_calculix`"#,
        reader: Reader::Elastic,
    },
    Keyword {
        names: &["DENSITY"],
        parameters: r#""#,
        notes: r#"used by `*DLOAD` `GRAV` and `CENTRIF`"#,
        reader: Reader::Density,
    },
    Keyword {
        names: &["EXPANSION"],
        parameters: r#"`TYPE=ISO` (default), `ORTHO` (material axes, rotated like the stiffness), `ANISO` (`a11, a22, a33, a12, a13, a23`); `ZERO=` (noted: no effect with constant coefficients)"#,
        notes: r#"one data line; a temperature on it is noted (one set of coefficients); temperature tables are errors naming the line; [below](#thermal-loads); ccx 2.20 on `crates/cli/tests/data/thermal_ring_*.inp`, CalculiX's `c3d6` against its `.dat.ref` ([`crates/cli/tests/thermal.rs`](../crates/cli/tests/thermal.rs))"#,
        reader: Reader::Expansion,
    },
    Keyword {
        names: &["INITIAL CONDITIONS"],
        parameters: r#"`TYPE=TEMPERATURE` (`node or node set, temperature`): the stress-free temperature"#,
        notes: r#"other types are errors naming the line"#,
        reader: Reader::InitialConditions,
    },
    Keyword {
        names: &["TEMPERATURE"],
        parameters: r#"`OP=MOD` / `NEW` (in a step): `node or node set, temperature` at the step's end"#,
        notes: r#"[below](#thermal-loads)"#,
        reader: Reader::Temperature,
    },
    Keyword {
        names: &["MEMBRANE"],
        parameters: r#"`ELSET=`, `MATERIAL=`"#,
        notes: r#"accepted with a note when its element set has no elements (CalculiX test decks carry such lines), else an error"#,
        reader: Reader::Membrane,
    },
    Keyword {
        names: &["DAMAGE INITIATION"],
        parameters: r#"see [cohesive decks](#cohesive-decks)"#,
        notes: r#""#,
        reader: Reader::DamageInitiation,
    },
    Keyword {
        names: &["DAMAGE EVOLUTION"],
        parameters: r#"see [cohesive decks](#cohesive-decks)"#,
        notes: r#""#,
        reader: Reader::DamageEvolution,
    },
    Keyword {
        names: &["DAMAGE STABILIZATION"],
        parameters: r#"see [cohesive decks](#cohesive-decks)"#,
        notes: r#""#,
        reader: Reader::DamageStabilization,
    },
    Keyword {
        names: &["ORIENTATION"],
        parameters: r#"`NAME=`, `SYSTEM=`, `DEFINITION=`; rectangular: points a, b; `SYSTEM=CYLINDRICAL`: two points a, b of the cylinder axis, exactly 6 values"#,
        notes: r#"rectangular: an Abaqus origin c (values 7-9) is used with a note, CalculiX 2.20 ignores it. Cylindrical: material axes 1 radial, 2 circumferential, 3 along b - a, evaluated at every integration point as CalculiX does; ccx 2.20 on `crates/cli/tests/data/cyl_ring_*.inp`. A second line with a non-zero rotation angle is an error naming the line"#,
        reader: Reader::Orientation,
    },
    Keyword {
        names: &["SOLID SECTION"],
        parameters: r#"`ELSET=`, `MATERIAL=`, `ORIENTATION=`, `OFFSET=0` (only 0); data line: the out-of-plane thickness of CPE and CPS elements (default 1; ignored by 3D and CAX elements); `COMPOSITE` with `STACK DIRECTION=1|2|3` (default 3), `LAYUP=` (kept, unused) and a data line per ply, bottom to top: `thickness, points (default 3, 1-5), material, orientation name or angle, ply name`"#,
        notes: r#"a damage material in a `*SOLID SECTION` is an error. [Composite sections](#composite-solid-sections): C3D8, C3D20, C3D20R, C3D27 only, integrated ply by ply with Gauss-Legendre points (Abaqus: Simpson); `tests/composite_section.rs`: [A B; B D] of a 2 x 2 C3D20 plate with one element through all plies within 1e-5 of CLT"#,
        reader: Reader::SolidSection,
    },
    Keyword {
        names: &["COHESIVE SECTION"],
        parameters: r#"`ELSET=`, `MATERIAL=`, `RESPONSE=TRACTION SEPARATION`, `THICKNESS=`; data line: constitutive thickness `T0` (default 1), then for COH2D4 the out-of-plane thickness (default 1)"#,
        notes: r#"[cohesive decks](#cohesive-decks)"#,
        reader: Reader::CohesiveSection,
    },
    Keyword {
        names: &["BOUNDARY"],
        parameters: r#"`OP=NEW`, `AMPLITUDE=`; dofs by number or `ENCASTRE`, `PINNED`, `XSYMM`, `YSYMM`, `ZSYMM`"#,
        notes: r#"[steps](#steps)"#,
        reader: Reader::Boundary,
    },
    Keyword {
        names: &["CLOAD"],
        parameters: r#"`OP=NEW`, `AMPLITUDE=`"#,
        notes: r#"several `*CLOAD`s on a dof within a step add up"#,
        reader: Reader::Cload,
    },
    Keyword {
        names: &["AMPLITUDE"],
        parameters: r#"`NAME=`, `TIME=STEP TIME` / `TOTAL TIME`, `SHIFTX=`, `SHIFTY=`, `DEFINITION=TABULAR`, `VALUE=RELATIVE`"#,
        notes: r#"ccx 2.20 on [`crates/cli/tests/data/amplitude_cube.inp`](../crates/cli/tests/data/amplitude_cube.inp); [below](#amplitudes)"#,
        reader: Reader::Amplitude,
    },
    Keyword {
        names: &["DLOAD"],
        parameters: r#"`P1`..`P6` face pressure on hexahedra, `P1`..`P5` on wedges, `GRAV`, `CENTRIF` (with the material's `*DENSITY`), `BX`/`BY`/`BZ` per volume; `OP=NEW`, `AMPLITUDE=`"#,
        notes: r#"`distributed_loads_match_calculix` ([`crates/cli/tests/data/dload_cube.inp`](../crates/cli/tests/data/dload_cube.inp)), `wedge_pressures_match_calculix` ([`crates/cli/tests/data/wedge_dload_c3d6.inp`](../crates/cli/tests/data/wedge_dload_c3d6.inp), [`crates/cli/tests/data/wedge_dload_c3d15.inp`](../crates/cli/tests/data/wedge_dload_c3d15.inp))"#,
        reader: Reader::Dload,
    },
    Keyword {
        names: &["SURFACE"],
        parameters: r#"`NAME=`, `TYPE=ELEMENT` (faces S1..S6 or P1..P6), `TYPE=NODE`"#,
        notes: r#"for `*DSLOAD`"#,
        reader: Reader::Surface,
    },
    Keyword {
        names: &["DSLOAD"],
        parameters: r#"`P`, `AMPLITUDE=`"#,
        notes: r#""#,
        reader: Reader::Dsload,
    },
    Keyword {
        names: &["EQUATION"],
        parameters: r#"node labels, or node sets paired member by member (Abaqus)"#,
        notes: r#"`equation_matches_calculix` ([`crates/cli/tests/data/equation_cube.inp`](../crates/cli/tests/data/equation_cube.inp)); [below](#equation)"#,
        reader: Reader::Equation,
    },
    Keyword {
        names: &["STEP"],
        parameters: r#"`NAME=`, `INC=n` (incremental runs), `NLGEOM` (large deformation for the whole run: [below](#nlgeom))"#,
        notes: r#"[steps](#steps)"#,
        reader: Reader::Step,
    },
    Keyword {
        names: &["STATIC"],
        parameters: r#"every CalculiX / Abaqus parameter, `RIKS`"#,
        notes: r#"[below](#static)"#,
        reader: Reader::Static,
    },
    Keyword {
        names: &["CONTROLS"],
        parameters: r#"`PARAMETERS=`, `RESET`"#,
        notes: r#"read and noted as unused: Junta's Newton criteria apply"#,
        reader: Reader::Controls,
    },
    Keyword {
        names: &["END STEP"],
        parameters: r#""#,
        notes: r#""#,
        reader: Reader::EndStep,
    },
    Keyword {
        names: &["INCLUDE"],
        parameters: r#"`INPUT=`"#,
        notes: r#"read in place, looked for next to the including file, then in the working directory; an error inside an included file names that file and its line"#,
        reader: Reader::Include,
    },
    Keyword {
        names: &["NODE PRINT"],
        parameters: r#"`NSET=`, `TOTALS=YES` / `ONLY`; variables `U`, `RF`"#,
        notes: r#"`node_print.csv`; [below](#node-print-and-el-print)"#,
        reader: Reader::NodePrint,
    },
    Keyword {
        names: &["EL PRINT"],
        parameters: r#"`ELSET=`, `GLOBAL=YES`; variables `S`, `E`, `ME`, `ENER`, `ELSE`, `EVOL`, `COORD` (`PEEQ` noted, not written)"#,
        notes: r#"`el_print.csv`; ccx 2.20 on [`crates/cli/tests/data/el_print_hex.inp`](../crates/cli/tests/data/el_print_hex.inp); [below](#node-print-and-el-print)"#,
        reader: Reader::ElPrint,
    },
    Keyword {
        names: &[
            "NODE FILE",
            "EL FILE",
            "NODE OUTPUT",
            "ELEMENT OUTPUT",
            "OUTPUT",
        ],
        parameters: r#""#,
        notes: r#"output requests: accepted and ignored with a note"#,
        reader: Reader::OutputRequest,
    },
];

/// The reader of keyword `kw` (upper case, without `*`), if any.
pub(super) fn reader_of(kw: &str) -> Option<Reader> {
    KEYWORDS
        .iter()
        .find(|k| k.names.contains(&kw))
        .map(|k| k.reader)
}

/// The keywords the reader understands, as an error message lists them:
/// `*HEADING, *NODE, ...`.
pub fn supported_keywords() -> String {
    KEYWORDS
        .iter()
        .flat_map(|k| k.names.iter().map(|n| format!("*{n}")))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The keyword table as the Markdown rows of `docs/decks.md`.
pub fn markdown_rows() -> String {
    let mut s = String::new();
    for k in KEYWORDS {
        let names: Vec<String> = k.names.iter().map(|n| format!("`*{n}`")).collect();
        let cell = |t: &str| {
            if t.is_empty() {
                " ".to_string()
            } else {
                format!(" {t} ")
            }
        };
        s += &format!(
            "| {} |{}|{}|\n",
            names.join(", "),
            cell(k.parameters),
            cell(k.notes)
        );
    }
    s
}

impl Parser<'_> {
    /// Read the `** junta: ...` comment directives (comments for Abaqus):
    /// `curve key=value ...` and `output every=N`.
    pub(super) fn directives(&mut self, text: &str) -> Result<(), InpError> {
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let Some(rest) = raw.trim().strip_prefix("**") else {
                continue;
            };
            let rest = rest.trim();
            let Some(body) = rest
                .get(..6)
                .filter(|h| h.eq_ignore_ascii_case("junta:"))
                .and_then(|_| rest.get(6..))
            else {
                continue;
            };
            let mut words = body.split_whitespace();
            let what = words.next().unwrap_or("").to_ascii_lowercase();
            let kw = format!("** junta: {what}");
            let mut pairs = Vec::new();
            for w in words {
                let Some((k, v)) = w.split_once('=') else {
                    return Err(self.invalid(line, &kw, format!("`{w}` is not `key=value`")));
                };
                pairs.push((k.to_ascii_lowercase(), v.to_string()));
            }
            let valid: &[&str] = match what.as_str() {
                "curve" => &[
                    "reaction_set",
                    "reaction_component",
                    "point_set",
                    "point_component",
                    "relative_to",
                ],
                "output" => &["every"],
                _ => {
                    return Err(self.invalid(
                        line,
                        "** junta:",
                        format!("unknown directive `{what}`; valid: `** junta: curve reaction_set=.. reaction_component=.. point_set=.. point_component=.. [relative_to=..]`, `** junta: output every=N`"),
                    ))
                }
            };
            if let Some((k, _)) = pairs.iter().find(|(k, _)| !valid.contains(&k.as_str())) {
                return Err(self.invalid(
                    line,
                    &kw,
                    format!("unknown key `{k}`; valid: {}", valid.join(", ")),
                ));
            }
            if what == "curve" {
                if let Some((l, _)) = &self.curve_directive {
                    return Err(self.invalid(
                        line,
                        &kw,
                        format!("a second curve directive (the first is at line {l})"),
                    ));
                }
                self.curve_directive = Some((line, pairs));
            } else {
                for (_, v) in pairs {
                    let n = self.label(line, &kw, "every", &v)?;
                    self.deck.every = Some(n);
                }
            }
        }
        Ok(())
    }

    /// Walk the keywords in order, each with its data lines, to its reader
    /// ([`Parser::keyword`]). A material is complete at the first keyword
    /// that is not one of its options; a step must be closed at the end.
    pub(super) fn run(&mut self, items: &[Item<'_>]) -> Result<(), InpError> {
        let mut i = 0;
        // data lines before any keyword
        if let Some(Item::Data { line, .. }) = items.first() {
            return Err(self.invalid(*line, "(none)", "data line before any keyword"));
        }
        while i < items.len() {
            let Item::Keyword { line, name, params } = &items[i] else {
                unreachable!("data lines are consumed by their keyword")
            };
            i += 1;
            let start = i;
            while i < items.len() && matches!(items[i], Item::Data { .. }) {
                i += 1;
            }
            let data: Vec<(usize, &[&str], bool)> = items[start..i]
                .iter()
                .map(|it| match it {
                    Item::Data {
                        line,
                        fields,
                        continues,
                        ..
                    } => (*line, fields.as_slice(), *continues),
                    Item::Keyword { .. } => unreachable!(),
                })
                .collect();
            if !matches!(
                name.as_str(),
                "ELASTIC"
                    | "DENSITY"
                    | "EXPANSION"
                    | "DAMAGE INITIATION"
                    | "DAMAGE EVOLUTION"
                    | "DAMAGE STABILIZATION"
            ) {
                self.finish_material()?;
            }
            self.keyword(*line, name, params, &items[start..i], &data)?;
        }
        self.finish_material()?;
        if let Some(s) = self.step_open {
            return Err(self.invalid(s, "STEP", "missing *END STEP at the end of the deck"));
        }
        Ok(())
    }

    /// One keyword (`kw` at `line`) with its data `items` (as `data`
    /// fields): dispatch to its reader.
    pub(super) fn keyword(
        &mut self,
        line: usize,
        kw: &str,
        params: &Params,
        items: &[Item<'_>],
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let Some(reader) = reader_of(kw) else {
            return Err(InpError::UnknownKeyword {
                file: self.file.into(),
                line,
                keyword: kw.into(),
                valid: supported_keywords(),
            });
        };
        match reader {
            Reader::Heading => self.heading(line, params, items),
            Reader::Node => self.node(line, params, data),
            Reader::Element => self.element(line, params, data),
            Reader::Set => self.set(line, kw, params, data),
            Reader::Material => self.material(line, params, data),
            Reader::Elastic => self.elastic(line, params, data),
            Reader::DamageInitiation => self.damage_initiation(line, params, data),
            Reader::DamageEvolution => self.damage_evolution(line, params, data),
            Reader::DamageStabilization => self.damage_stabilization(line, params, data),
            Reader::Density => self.density(line, params, data),
            Reader::Controls => self.controls(line, params),
            Reader::Expansion => self.expansion(line, params, data),
            Reader::InitialConditions => self.initial_conditions(line, params, data),
            Reader::Temperature => self.temperature(line, params, data),
            Reader::Membrane => self.membrane(line, params, data),
            Reader::SolidSection => self.solid_section(line, params, data),
            Reader::CohesiveSection => self.cohesive_section(line, params, data),
            Reader::Orientation => self.orientation(line, params, data),
            Reader::Boundary => self.boundary(line, params, data),
            Reader::Cload => self.cload(line, params, data),
            Reader::Amplitude => self.amplitude(line, params, data),
            Reader::Equation => self.equation(line, params, data),
            Reader::Surface => self.surface(line, params, data),
            Reader::Dload => self.dload(line, params, data),
            Reader::Dsload => self.dsload(line, params, data),
            Reader::Step => self.step(line, params, data),
            Reader::Static => self.static_procedure(line, params, data),
            Reader::EndStep => {
                self.check_params(line, kw, params, &[])?;
                if self.step_open.take().is_none() {
                    return Err(self.invalid(line, kw, "*END STEP without *STEP"));
                }
                Ok(())
            }
            Reader::NodePrint => self.node_print(line, params, data),
            Reader::ElPrint => self.el_print(line, params, data),
            Reader::Include => Err(self.invalid(
                line,
                "INCLUDE",
                "an included file is read in place only when the deck is read from a file (read_inp); this text was given without one",
            )),
            Reader::OutputRequest => {
                self.deck.notes.push(format!(
                    "line {line}: *{kw} ignored (outputs are chosen in the scene); {} data line(s) skipped",
                    data.len()
                ));
                Ok(())
            }
        }
    }

    /// `*HEADING`: its data lines, as written, are the deck's heading.
    pub(super) fn heading(
        &mut self,
        line: usize,
        params: &Params,
        items: &[Item<'_>],
    ) -> Result<(), InpError> {
        self.check_params(line, "HEADING", params, &[])?;
        let text: Vec<&str> = items
            .iter()
            .filter_map(|it| match it {
                Item::Data { raw, .. } => Some(*raw),
                Item::Keyword { .. } => None,
            })
            .collect();
        self.deck.heading = text.join("\n");
        Ok(())
    }

    /// `*CONTROLS [, PARAMETERS=] [, RESET]`: CalculiX's and Abaqus'
    /// solution controls (convergence criteria, time incrementation),
    /// read and noted as unused: Junta's Newton criteria apply.
    pub(super) fn controls(&mut self, line: usize, params: &Params) -> Result<(), InpError> {
        self.check_params(
            line,
            "CONTROLS",
            params,
            &["PARAMETERS", "RESET", "ANALYSIS", "TYPE"],
        )?;
        self.deck.notes.push(format!(
            "line {line}: *CONTROLS read but unused: Junta's own Newton criteria apply (out-of-balance force 1e-6 of the largest force, see [analysis.newton] in docs/path-following.md)"
        ));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `docs/decks.md`'s keyword table is this table, row for row.
    #[test]
    fn docs_table_is_the_keyword_table() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/decks.md");
        let docs = std::fs::read_to_string(path).unwrap();
        let rows = markdown_rows();
        assert!(
            docs.contains(&rows),
            "docs/decks.md's keyword table differs from input::inp::KEYWORDS; its rows should be:\n{rows}"
        );
    }

    /// Every keyword the parser dispatches is listed in the error message
    /// for an unknown one, `*ORIENTATION` among them.
    #[test]
    fn every_keyword_of_the_table_is_listed_and_dispatched() {
        let listed = supported_keywords();
        for k in KEYWORDS {
            for n in k.names {
                assert!(listed.contains(&format!("*{n}")), "{n}");
                assert_eq!(reader_of(n), Some(k.reader));
            }
        }
        assert!(listed.contains("*ORIENTATION"));
        assert_eq!(reader_of("FROBNICATE"), None);
    }
}
