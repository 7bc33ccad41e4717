//! Loads and steps: `*STEP`, `*STATIC`, `*BOUNDARY`, `*CLOAD`, `*DLOAD`,
//! `*DSLOAD`, `*AMPLITUDE`, `*EQUATION`, temperatures, and the print
//! requests `*NODE PRINT` / `*EL PRINT`.

use super::*;

/// Parameters of `*STATIC` that do not change a linear-static or
/// incremental result of Junta (noted and skipped): CalculiX `TIME RESET`,
/// `TOTAL TIME AT START` (time labels only), Abaqus `ALLSDTOL`, `CONTINUE`,
/// `FACTOR` (automatic stabilisation controls without `STABILIZE`).
const STATIC_NOTED: [&str; 5] = [
    "TIME RESET",
    "TOTAL TIME AT START",
    "ALLSDTOL",
    "CONTINUE",
    "FACTOR",
];

/// Parameters of `*STATIC` that change the answer and that Junta does not
/// have: an error naming the line.
const STATIC_REFUSED: [(&str, &str); 3] = [
    ("STABILIZE", "automatic viscous stabilisation"),
    ("FULLY PLASTIC", "fully plastic limit analysis"),
    ("LONG TERM", "long-term viscoelastic response"),
];

impl Parser<'_> {
    /// `node or node set, temperature` data lines of `kw` into
    /// [`InpDeck::temperatures`].
    pub(super) fn temperature_lines(
        &mut self,
        kw: &str,
        data: &[(usize, &[&str], bool)],
        step: Option<usize>,
        op_new: bool,
    ) -> Result<(), InpError> {
        for &(dl, f, _) in data {
            let values: Vec<&str> = f.iter().copied().filter(|s| !s.is_empty()).collect();
            if values.len() != 2 {
                return Err(self.invalid(dl, kw, "expected `node or node set, temperature`"));
            }
            let value = self.float(dl, kw, "temperature", values[1])?;
            self.deck.temperatures.push(InpTemperature {
                target: values[0].into(),
                nodes: Vec::new(),
                value,
                step,
                op_new,
                line: dl,
            });
        }
        Ok(())
    }

    /// `*INITIAL CONDITIONS, TYPE=TEMPERATURE`: the initial (stress-free)
    /// temperature of nodes; other types are refused.
    pub(super) fn initial_conditions(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "INITIAL CONDITIONS";
        self.check_params(line, kw, params, &["TYPE"])?;
        self.model_data_only(line, kw)?;
        let ty = Self::param(params, "TYPE")
            .and_then(|(_, v)| v.as_deref())
            .map(norm_key)
            .unwrap_or_default();
        if ty != "TEMPERATURE" {
            return Err(InpError::Parameter {
                file: self.file.into(),
                line,
                keyword: kw.into(),
                parameter: format!("TYPE={ty}"),
                valid: "TYPE=TEMPERATURE".into(),
            });
        }
        self.temperature_lines(kw, data, None, false)
    }

    /// `*TEMPERATURE [, OP=MOD | NEW]` inside a step: the temperature of
    /// nodes at the end of the step.
    pub(super) fn temperature(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "TEMPERATURE";
        self.check_params(line, kw, params, &["OP"])?;
        if self.step_open.is_none() {
            return Err(self.invalid(
                line,
                kw,
                "*TEMPERATURE belongs inside a *STEP (the initial temperature is *INITIAL CONDITIONS, TYPE=TEMPERATURE)",
            ));
        }
        let op_new = self.op_new(line, kw, params)?;
        let step = Some(self.deck.steps.len() - 1);
        self.temperature_lines(kw, data, step, op_new)
    }

    /// `*STEP [, NAME=] [, NLGEOM[=YES|NO]] [, INC=]`: opens a step (a
    /// description line is skipped).
    pub(super) fn step(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "STEP";
        self.check_params(line, kw, params, &["NAME", "NLGEOM", "INC"])?;
        if let Some(s) = self.step_open {
            return Err(self.invalid(
                line,
                kw,
                format!("*STEP inside the *STEP of line {s}; close it with *END STEP"),
            ));
        }
        let nlgeom = match Self::param(params, "NLGEOM") {
            None => false,
            Some((_, None)) => true,
            Some((_, Some(v))) => match v.to_uppercase().as_str() {
                "YES" => true,
                "NO" => false,
                _ => {
                    return Err(InpError::Parameter {
                        file: self.file.into(),
                        line,
                        keyword: kw.into(),
                        parameter: format!("NLGEOM={v}"),
                        valid: "NLGEOM, NLGEOM=YES, NLGEOM=NO".into(),
                    })
                }
            },
        };
        let max_increments = match Self::param(params, "INC") {
            Some((_, Some(v))) => Some(self.label(line, kw, "INC", v)?),
            Some((_, None)) => {
                return Err(self.invalid(line, kw, "INC needs a value, e.g. INC=100"))
            }
            None => None,
        };
        let name = Self::param(params, "NAME").and_then(|(_, v)| v.clone());
        if let Some((dl, _, _)) = data.first() {
            // Abaqus allows a step description line
            self.deck
                .notes
                .push(format!("line {dl}: *STEP description skipped"));
        }
        self.deck.steps.push(InpStep {
            name,
            nlgeom,
            max_increments,
            static_procedure: None,
            line,
        });
        self.step_open = Some(line);
        Ok(())
    }

    /// `*STATIC [, DIRECT] [, SOLVER=] [, RIKS]` inside a step: parameters
    /// that change nothing are noted, unsupported ones refused; the data
    /// line is read by [`Parser::static_values`].
    pub(super) fn static_procedure(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "STATIC";
        let mut valid = vec!["DIRECT", "SOLVER", "RIKS"];
        valid.extend(STATIC_NOTED);
        valid.extend(STATIC_REFUSED.iter().map(|(k, _)| *k));
        self.check_params(line, kw, params, &valid)?;
        for (k, what) in STATIC_REFUSED {
            if Self::param(params, k).is_some() {
                return Err(self.invalid(
                    line,
                    kw,
                    format!("*STATIC, {k} ({what}) is not supported"),
                ));
            }
        }
        for k in STATIC_NOTED {
            if Self::param(params, k).is_some() {
                self.deck.notes.push(format!(
                    "line {line}: *STATIC, {k} does not change Junta's results; skipped"
                ));
            }
        }
        let solver = match Self::param(params, "SOLVER") {
            None => None,
            Some((_, Some(v))) if !v.is_empty() => Some(v.to_uppercase()),
            Some(_) => {
                return Err(self.invalid(
                    line,
                    kw,
                    "SOLVER needs a value (SPOOLES, PARDISO, PASTIX, ITERATIVE SCALING, ITERATIVE CHOLESKY)",
                ))
            }
        };
        if self.step_open.is_none() {
            return Err(self.invalid(line, kw, "*STATIC must be inside *STEP ... *END STEP"));
        }
        let riks = Self::param(params, "RIKS").is_some();
        let v = self.static_values(line, riks, data)?;
        let step = self.deck.steps.last_mut().unwrap();
        step.static_procedure = Some(InpStatic {
            initial_increment: v[0],
            period: v[1],
            min_increment: v[2],
            max_increment: v[3],
            direct: Self::param(params, "DIRECT").is_some(),
            solver,
            riks: riks.then_some(InpRiks {
                max_load_factor: v[4],
            }),
            line,
        });
        Ok(())
    }

    /// The data line of `*STATIC`: initial increment, period, minimum and
    /// maximum increment; with RIKS also the maximum load factor and the
    /// (noted, unsupported) monitored node, dof and displacement. Empty
    /// fields are `None`.
    pub(super) fn static_values(
        &mut self,
        line: usize,
        riks: bool,
        data: &[(usize, &[&str], bool)],
    ) -> Result<[Option<f64>; 8], InpError> {
        let kw = "STATIC";
        if data.len() > 1 {
            return Err(self.invalid(data[1].0, kw, "expected at most one data line"));
        }
        let mut v = [None; 8];
        if let Some((dl, f, _)) = data.first() {
            let most = if riks { 8 } else { 4 };
            if f.len() > most {
                return Err(self.invalid(
                    *dl,
                    kw,
                    if riks {
                        "expected at most 8 values: initial arc length, period, minimum, maximum arc length, maximum load factor, node, dof, displacement"
                    } else {
                        "expected at most 4 values: initial increment, period, minimum, maximum increment"
                    },
                ));
            }
            let names = [
                "initial increment",
                "time period",
                "minimum increment",
                "maximum increment",
                "maximum load proportionality factor",
                "monitored node",
                "monitored degree of freedom",
                "finishing displacement",
            ];
            for (k, t) in f.iter().enumerate() {
                if !t.is_empty() {
                    v[k] = Some(self.float(*dl, kw, names[k], t)?);
                }
            }
        }
        if riks && v[5..].iter().any(Option::is_some) {
            self.deck.notes.push(format!(
                "line {line}: *STATIC, RIKS: the stop on a node's displacement (values 6-8) is not supported; the run ends at the maximum load factor or after INC increments"
            ));
        }
        Ok(v)
    }

    /// `*NODE PRINT, NSET= [, TOTALS=]`: variables of the data lines (`U`
    /// when none).
    pub(super) fn node_print(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "NODE PRINT";
        let nset = self.required(line, kw, params, "NSET")?;
        let totals = match Self::param(params, "TOTALS") {
            None => "NO".to_string(),
            Some((_, Some(v))) => v.to_uppercase(),
            Some((_, None)) => "YES".to_string(),
        };
        if !["NO", "YES", "ONLY"].contains(&totals.as_str()) {
            return Err(self.invalid(
                line,
                kw,
                format!("TOTALS={totals}: valid are YES, ONLY, NO"),
            ));
        }
        let variables = data
            .iter()
            .flat_map(|(_, f, _)| f.iter())
            .filter(|t| !t.is_empty())
            .map(|t| t.to_uppercase())
            .collect::<Vec<_>>();
        let variables = if variables.is_empty() {
            vec!["U".to_string()]
        } else {
            variables
        };
        self.deck.node_prints.push(InpNodePrint {
            nset,
            variables,
            totals,
            step: self.step_open.map(|_| self.deck.steps.len() - 1),
            line,
        });
        Ok(())
    }

    /// `*EL PRINT, ELSET= [, GLOBAL=]`: variables of the data lines (`S`
    /// when none).
    pub(super) fn el_print(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "EL PRINT";
        let elset = self.required(line, kw, params, "ELSET")?;
        // CalculiX prints oriented elements in their material
        // axes unless GLOBAL=YES
        let global = match Self::param(params, "GLOBAL")
            .and_then(|(_, v)| v.as_deref())
            .map(norm_key)
            .as_deref()
        {
            None | Some("NO") => false,
            Some("YES") => true,
            Some(v) => {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    parameter: format!("GLOBAL={v}"),
                    valid: "GLOBAL=YES or GLOBAL=NO".into(),
                })
            }
        };
        let mut variables = data
            .iter()
            .flat_map(|(_, f, _)| f.iter())
            .filter(|t| !t.is_empty())
            .map(|t| t.to_uppercase())
            .collect::<Vec<_>>();
        if variables.is_empty() {
            variables.push("S".to_string());
        }
        self.deck.el_prints.push(InpElPrint {
            elset,
            variables,
            global,
            step: self.step_open.map(|_| self.deck.steps.len() - 1),
            line,
        });
        Ok(())
    }

    pub(super) fn boundary(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "BOUNDARY";
        self.check_params(line, kw, params, &["OP", "AMPLITUDE"])?;
        let op_new = self.op_new(line, kw, params)?;
        let amplitude = self.amplitude_param(line, kw, params)?;
        for &(dl, f, _) in data {
            let f: Vec<&str> = f.to_vec();
            let target = f.first().copied().unwrap_or("");
            if target.is_empty() || f.len() < 2 || f.len() > 4 {
                return Err(self.invalid(
                    dl,
                    kw,
                    "expected `node or node set, first dof[, last dof[, value]]`",
                ));
            }
            let (first, last) = match f[1].to_uppercase().as_str() {
                "ENCASTRE" | "PINNED" => (1, 3),
                "XSYMM" => (1, 1),
                "YSYMM" => (2, 2),
                "ZSYMM" => (3, 3),
                _ => {
                    let a = self.dof(dl, kw, f[1])?;
                    let b = match f.get(2) {
                        Some(t) if !t.is_empty() => self.dof(dl, kw, t)?,
                        _ => a,
                    };
                    if b < a {
                        return Err(self.invalid(
                            dl,
                            kw,
                            format!("last dof {b} is below first dof {a}"),
                        ));
                    }
                    (a, b)
                }
            };
            let value = match f.get(3) {
                Some(t) if !t.is_empty() => self.float(dl, kw, "value", t)?,
                _ => 0.0,
            };
            self.boundary_targets.push(PendingTarget {
                target: target.into(),
                line: dl,
                keyword: "BOUNDARY",
            });
            self.deck.boundaries.push(InpBoundary {
                target: target.into(),
                nodes: Vec::new(),
                first_dof: first,
                last_dof: last,
                value,
                in_step: self.step_open.is_some(),
                step: self.step_open.map(|_| self.deck.steps.len() - 1),
                op_new,
                keyword_line: line,
                line: dl,
                amplitude: None,
            });
            self.refer_amplitude(
                AmplitudeUse::Boundary,
                self.deck.boundaries.len() - 1,
                &amplitude,
                line,
            );
        }
        Ok(())
    }

    /// `*AMPLITUDE, NAME= [, TIME=STEP TIME | TOTAL TIME] [,
    /// DEFINITION=TABULAR] [, VALUE=RELATIVE] [, SHIFTX=] [, SHIFTY=]`:
    /// data lines of `time, value` pairs (any number per line).
    pub(super) fn amplitude(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "AMPLITUDE";
        self.check_params(
            line,
            kw,
            params,
            &["NAME", "TIME", "DEFINITION", "VALUE", "SHIFTX", "SHIFTY"],
        )?;
        let name = self.required(line, kw, params, "NAME")?;
        if self
            .deck
            .amplitudes
            .iter()
            .any(|a| a.name.eq_ignore_ascii_case(&name))
        {
            return Err(self.invalid(line, kw, format!("amplitude `{name}` is defined twice")));
        }
        let total_time = self.two_way(
            line,
            kw,
            params,
            ("TIME", "STEP TIME", "TOTAL TIME"),
            "TIME=STEP TIME, TIME=TOTAL TIME",
        )?;
        for (key, valid) in [("DEFINITION", "TABULAR"), ("VALUE", "RELATIVE")] {
            if let Some((_, v)) = Self::param(params, key) {
                if !v.as_deref().is_some_and(|v| v.eq_ignore_ascii_case(valid)) {
                    return Err(InpError::Parameter {
                        file: self.file.into(),
                        line,
                        keyword: kw.into(),
                        parameter: format!("{key}={}", v.as_deref().unwrap_or("")),
                        valid: format!("{key}={valid} (the only form Junta reads)"),
                    });
                }
            }
        }
        let shift = |key: &str| -> Result<f64, InpError> {
            match Self::param(params, key) {
                None => Ok(0.0),
                Some((_, Some(v))) => {
                    let x = self.float(line, kw, key, v)?;
                    if x.is_finite() {
                        Ok(x)
                    } else {
                        Err(self.invalid(line, kw, format!("{key}={v} is not finite")))
                    }
                }
                Some((_, None)) => Err(self.invalid(line, kw, format!("{key}= needs a value"))),
            }
        };
        let (dx, dy) = (shift("SHIFTX")?, shift("SHIFTY")?);
        let mut points: Vec<(f64, f64)> = Vec::new();
        for &(dl, f, _) in data {
            let f: Vec<&str> = f.iter().copied().filter(|t| !t.trim().is_empty()).collect();
            if !f.len().is_multiple_of(2) {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!("{} values: expected `time, value` pairs", f.len()),
                ));
            }
            for pair in f.chunks(2) {
                let t = self.float(dl, kw, "time", pair[0])? + dx;
                let a = self.float(dl, kw, "amplitude value", pair[1])? + dy;
                if !(t.is_finite() && a.is_finite()) {
                    return Err(self.invalid(dl, kw, "times and values must be finite"));
                }
                if let Some(&(t0, _)) = points.last() {
                    if t < t0 {
                        return Err(self.invalid(
                            dl,
                            kw,
                            format!("time {t} is earlier than the point before it ({t0}): times must not decrease"),
                        ));
                    }
                }
                points.push((t, a));
            }
        }
        if points.is_empty() {
            return Err(self.invalid(line, kw, "no `time, value` pairs follow"));
        }
        self.deck.amplitudes.push(InpAmplitude {
            name,
            points,
            total_time,
            line,
        });
        Ok(())
    }

    /// Keep the `AMPLITUDE=` name of record `index` of list `what` (if
    /// any) for resolution when the deck is read.
    pub(super) fn refer_amplitude(
        &mut self,
        what: AmplitudeUse,
        index: usize,
        amplitude: &Option<String>,
        line: usize,
    ) {
        if let Some(name) = amplitude {
            self.amplitude_refs.push((what, index, name.clone(), line));
        }
    }

    /// The `AMPLITUDE=` parameter of a load keyword: the name, only inside
    /// a step (an amplitude scales a load over the step time).
    pub(super) fn amplitude_param(
        &self,
        line: usize,
        kw: &str,
        params: &Params,
    ) -> Result<Option<String>, InpError> {
        match Self::param(params, "AMPLITUDE") {
            None => Ok(None),
            Some((_, Some(name))) if !name.is_empty() => {
                if self.step_open.is_none() {
                    return Err(self.invalid(
                        line,
                        kw,
                        "AMPLITUDE= scales a load over a step's time; it is only valid inside *STEP",
                    ));
                }
                Ok(Some(name.clone()))
            }
            Some(_) => Err(self.invalid(line, kw, "AMPLITUDE= needs the name of an *AMPLITUDE")),
        }
    }

    pub(super) fn cload(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "CLOAD";
        self.check_params(line, kw, params, &["OP", "AMPLITUDE"])?;
        let op_new = self.op_new(line, kw, params)?;
        let amplitude = self.amplitude_param(line, kw, params)?;
        for &(dl, f, _) in data {
            if f.len() != 3 || f[0].is_empty() {
                return Err(self.invalid(dl, kw, "expected `node or node set, dof, value`"));
            }
            let dof = self.dof(dl, kw, f[1])?;
            let value = self.float(dl, kw, "value", f[2])?;
            self.cload_targets.push(PendingTarget {
                target: f[0].into(),
                line: dl,
                keyword: "CLOAD",
            });
            self.deck.cloads.push(InpCload {
                target: f[0].into(),
                nodes: Vec::new(),
                dof,
                value,
                in_step: self.step_open.is_some(),
                step: self.step_open.map(|_| self.deck.steps.len() - 1),
                op_new,
                keyword_line: line,
                line: dl,
                amplitude: None,
            });
            self.refer_amplitude(
                AmplitudeUse::Cload,
                self.deck.cloads.len() - 1,
                &amplitude,
                line,
            );
        }
        Ok(())
    }

    /// `*EQUATION`: per equation a line with the number of terms N, then N
    /// `node (or node set), dof, coefficient` triples over as many lines as
    /// needed (CalculiX and Abaqus put at most four per line).
    pub(super) fn equation(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "EQUATION";
        self.check_params(line, kw, params, &[])?;
        self.model_data_only(line, kw)?;
        if data.is_empty() {
            return Err(self.invalid(
                line,
                kw,
                "no equation follows (expected the number of terms)",
            ));
        }
        let mut k = 0;
        while k < data.len() {
            let (dl, f, _) = data[k];
            if f.len() != 1 {
                return Err(self.invalid(
                    dl,
                    kw,
                    "expected the number of terms of the next equation alone on its line",
                ));
            }
            let n = self.label(dl, kw, "number of terms", f[0])?;
            if n < 2 {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!("an equation needs at least 2 terms, not {n}"),
                ));
            }
            k += 1;
            let mut fields: Vec<(usize, &str)> = Vec::with_capacity(3 * n);
            while fields.len() < 3 * n {
                let Some(&(tl, tf, _)) = data.get(k) else {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!(
                            "the equation announces {n} terms but the data ends after {} fields (3 per term: node, dof, coefficient)",
                            fields.len()
                        ),
                    ));
                };
                fields.extend(tf.iter().map(|t| (tl, *t)));
                k += 1;
            }
            if fields.len() != 3 * n {
                return Err(self.invalid(
                    fields[3 * n].0,
                    kw,
                    format!(
                        "the equation has {n} terms, so {} fields, but its lines hold {}",
                        3 * n,
                        fields.len()
                    ),
                ));
            }
            let mut terms = Vec::with_capacity(n);
            for t in fields.chunks(3) {
                let (tl, target) = t[0];
                if target.is_empty() {
                    return Err(self.invalid(
                        tl,
                        kw,
                        "expected `node or node set, dof, coefficient`",
                    ));
                }
                let dof = self.dof(t[1].0, kw, t[1].1)?;
                let a = self.float(t[2].0, kw, "coefficient", t[2].1)?;
                terms.push((target.to_string(), dof, a));
            }
            if terms[0].2 == 0.0 {
                return Err(self.invalid(
                    dl,
                    kw,
                    "the first (dependent) term has coefficient 0; it must be non-zero",
                ));
            }
            self.equation_terms.push((dl, terms));
        }
        Ok(())
    }

    /// `*DLOAD [, OP=]`: `element or elset, label, values`: `P1`..`P6`
    /// pressure, `GRAV, g, nx, ny, nz`, `CENTRIF, omega^2, point, axis`,
    /// `BX|BY|BZ, force per volume`.
    pub(super) fn dload(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DLOAD";
        self.check_params(line, kw, params, &["OP", "AMPLITUDE"])?;
        let op_new = self.op_new(line, kw, params)?;
        let amplitude = self.amplitude_param(line, kw, params)?;
        for &(dl, f, _) in data {
            if f.len() < 3 || f[0].is_empty() {
                return Err(self.invalid(
                    dl,
                    kw,
                    "expected `element or element set, load label, magnitude [, ...]`",
                ));
            }
            let label = f[1].trim().to_uppercase();
            let want = |n: usize| -> Result<(), InpError> {
                if f.len() != n {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!(
                            "load {label} takes {} values after the label, not {}",
                            n - 2,
                            f.len() - 2
                        ),
                    ));
                }
                Ok(())
            };
            let (kind, face) = match label.as_str() {
                "GRAV" => {
                    want(6)?;
                    let g = self.float(dl, kw, "GRAV magnitude", f[2])?;
                    let d = self.vector3(dl, kw, "GRAV direction", &f[3..6])?;
                    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    if !(l > 0.0 && l.is_finite()) {
                        return Err(self.invalid(dl, kw, "GRAV direction (values 4-6) has no length"));
                    }
                    (InpDloadKind::Gravity([g * d[0] / l, g * d[1] / l, g * d[2] / l]), 0)
                }
                "CENTRIF" => {
                    want(9)?;
                    let omega2 = self.float(dl, kw, "CENTRIF omega^2", f[2])?;
                    let point = self.vector3(dl, kw, "CENTRIF axis point", &f[3..6])?;
                    let axis = self.vector3(dl, kw, "CENTRIF axis direction", &f[6..9])?;
                    if axis.iter().all(|&a| a == 0.0) {
                        return Err(self.invalid(dl, kw, "CENTRIF axis direction (values 7-9) is zero"));
                    }
                    (InpDloadKind::Centrifugal { omega2, point, axis }, 0)
                }
                "BX" | "BY" | "BZ" => {
                    want(3)?;
                    let b = self.float(dl, kw, "body force", f[2])?;
                    let mut v = [0.0; 3];
                    v[(label.as_bytes()[1] - b'X') as usize] = b;
                    (InpDloadKind::BodyForce(v), 0)
                }
                l if l.starts_with('P') && l.len() == 2 => {
                    want(3)?;
                    let face = self.face_label(dl, kw, l, 'P')?;
                    (InpDloadKind::Pressure(self.float(dl, kw, "pressure", f[2])?), face)
                }
                _ => {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!("load label `{}` is not supported; valid: P1..P6 (pressure on a face), GRAV, CENTRIF, BX, BY, BZ", f[1]),
                    ))
                }
            };
            let target = DloadTarget::Elements {
                target: f[0].to_string(),
                face,
            };
            self.push_dload(target, label, kind, op_new, (line, dl), &amplitude);
        }
        Ok(())
    }

    /// One distributed load of the open step (or of the model): its
    /// target, the load, and its amplitude, if the keyword names one;
    /// `(line, dl)`: the keyword line and the data line.
    fn push_dload(
        &mut self,
        target: DloadTarget,
        label: String,
        kind: InpDloadKind,
        op_new: bool,
        (line, dl): (usize, usize),
        amplitude: &Option<String>,
    ) {
        self.dload_targets.push(target);
        self.deck.dloads.push(InpDload {
            label,
            kind,
            elements: Vec::new(),
            step: self.step_open.map(|_| self.deck.steps.len() - 1),
            op_new,
            keyword_line: line,
            line: dl,
            amplitude: None,
        });
        self.refer_amplitude(
            AmplitudeUse::Dload,
            self.deck.dloads.len() - 1,
            amplitude,
            line,
        );
    }

    /// `*DSLOAD [, OP=]`: `surface, P, pressure` on an element surface.
    pub(super) fn dsload(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DSLOAD";
        self.check_params(line, kw, params, &["OP", "AMPLITUDE"])?;
        let op_new = self.op_new(line, kw, params)?;
        let amplitude = self.amplitude_param(line, kw, params)?;
        for &(dl, f, _) in data {
            if f.len() != 3 || f[0].is_empty() {
                return Err(self.invalid(dl, kw, "expected `surface, P, pressure`"));
            }
            if !f[1].trim().eq_ignore_ascii_case("P") {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!(
                        "load label `{}` is not supported; valid: P (uniform pressure)",
                        f[1]
                    ),
                ));
            }
            let p = self.float(dl, kw, "pressure", f[2])?;
            let target = DloadTarget::Surface(f[0].to_string());
            let kind = InpDloadKind::Pressure(p);
            self.push_dload(target, "P".into(), kind, op_new, (line, dl), &amplitude);
        }
        Ok(())
    }
}
