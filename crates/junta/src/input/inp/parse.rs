//! The parser's helpers: the error of a keyword, parameter checks, numbers,
//! labels, dofs, and the node and element sets a keyword names.

use super::*;

impl Parser<'_> {
    pub(super) fn invalid(
        &self,
        line: usize,
        keyword: &str,
        message: impl Into<String>,
    ) -> InpError {
        InpError::Invalid {
            file: self.file.into(),
            line,
            keyword: keyword.into(),
            message: message.into(),
        }
    }

    pub(super) fn check_params(
        &self,
        line: usize,
        keyword: &str,
        params: &Params,
        valid: &[&str],
    ) -> Result<(), InpError> {
        for (k, _) in params {
            if !valid.contains(&k.as_str()) {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: keyword.into(),
                    parameter: k.clone(),
                    valid: if valid.is_empty() {
                        "(none)".into()
                    } else {
                        valid.join(", ")
                    },
                });
            }
        }
        Ok(())
    }

    /// A parameter with two values `(key, default, other)`: `false` when
    /// absent or `default`, `true` for `other` (case-insensitive), an error
    /// listing `valid` otherwise.
    pub(super) fn two_way(
        &self,
        line: usize,
        keyword: &str,
        params: &Params,
        (key, default, other): (&str, &str, &str),
        valid: &str,
    ) -> Result<bool, InpError> {
        match Self::param(params, key) {
            None => Ok(false),
            Some((_, Some(v))) if v.eq_ignore_ascii_case(default) => Ok(false),
            Some((_, Some(v))) if v.eq_ignore_ascii_case(other) => Ok(true),
            Some((_, v)) => Err(InpError::Parameter {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                parameter: format!("{key}={}", v.as_deref().unwrap_or("")),
                valid: valid.into(),
            }),
        }
    }

    pub(super) fn param<'p>(params: &'p Params, key: &str) -> Option<&'p (String, Option<String>)> {
        params.iter().find(|(k, _)| k == key)
    }

    pub(super) fn required(
        &self,
        line: usize,
        keyword: &str,
        params: &Params,
        key: &str,
    ) -> Result<String, InpError> {
        match Self::param(params, key) {
            Some((_, Some(v))) if !v.is_empty() => Ok(v.clone()),
            _ => Err(InpError::MissingParameter {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                parameter: format!("{key}="),
            }),
        }
    }

    pub(super) fn float(
        &self,
        line: usize,
        keyword: &str,
        what: &str,
        text: &str,
    ) -> Result<f64, InpError> {
        let t = text.replace(['d', 'D'], "e");
        t.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| InpError::BadNumber {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                what: what.into(),
                text: text.into(),
                expected: "number",
            })
    }

    pub(super) fn label(
        &self,
        line: usize,
        keyword: &str,
        what: &str,
        text: &str,
    ) -> Result<usize, InpError> {
        text.parse::<usize>()
            .ok()
            .filter(|&x| x > 0)
            .ok_or_else(|| InpError::BadNumber {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                what: what.into(),
                text: text.into(),
                expected: "positive integer label",
            })
    }

    pub(super) fn dof(&self, line: usize, keyword: &str, text: &str) -> Result<usize, InpError> {
        let d = self.label(line, keyword, "degree of freedom", text)?;
        if !(1..=3).contains(&d) {
            return Err(self.invalid(
                line,
                keyword,
                format!("degree of freedom {d} is not supported; valid: 1, 2, 3 (displacements of solids)"),
            ));
        }
        Ok(d)
    }

    pub(super) fn unknown_set(
        &self,
        line: usize,
        keyword: &str,
        kind: &'static str,
        name: &str,
    ) -> InpError {
        let sets = if kind == "node set" {
            &self.nsets
        } else {
            &self.elsets
        };
        let valid = if sets.is_empty() {
            "(none)".to_string()
        } else {
            sets.iter()
                .map(|s| s.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        InpError::UnknownName {
            file: self.file.into(),
            line,
            keyword: keyword.into(),
            kind,
            name: name.into(),
            valid,
        }
    }

    pub(super) fn node_of(
        &self,
        line: usize,
        keyword: &str,
        label: usize,
    ) -> Result<usize, InpError> {
        self.node_id
            .get(&label)
            .copied()
            .ok_or_else(|| InpError::UndefinedLabel {
                file: self.file.into(),
                line,
                keyword: keyword.into(),
                kind: "node",
                label,
            })
    }

    pub(super) fn set_mut(
        sets: &mut Vec<NamedSet>,
        index: &mut HashMap<String, usize>,
        name: &str,
    ) -> usize {
        let key = name.to_uppercase();
        *index.entry(key).or_insert_with(|| {
            sets.push(NamedSet {
                name: name.to_string(),
                members: Vec::new(),
            });
            sets.len() - 1
        })
    }

    /// Resolve a node target (label or node set) to node ids.
    pub(super) fn node_target(
        &self,
        line: usize,
        keyword: &str,
        target: &str,
    ) -> Result<Vec<usize>, InpError> {
        if target.chars().all(|c| c.is_ascii_digit()) {
            let l = self.label(line, keyword, "node label", target)?;
            Ok(vec![self.node_of(line, keyword, l)?])
        } else {
            match self.nset_index.get(&target.to_uppercase()) {
                Some(&i) => Ok(self.nsets[i].members.clone()),
                None => Err(self.unknown_set(line, keyword, "node set", target)),
            }
        }
    }

    pub(super) fn model_data_only(&self, line: usize, keyword: &str) -> Result<(), InpError> {
        if let Some(s) = self.step_open {
            return Err(self.invalid(
                line,
                keyword,
                format!(
                    "model data is not allowed inside the *STEP of line {s}; move it before *STEP"
                ),
            ));
        }
        Ok(())
    }

    pub(super) fn bad_param(
        &self,
        line: usize,
        kw: &str,
        parameter: String,
        valid: &str,
    ) -> InpError {
        InpError::Parameter {
            file: self.file.into(),
            line,
            keyword: kw.into(),
            parameter,
            valid: valid.into(),
        }
    }

    /// The `OP` parameter of `*BOUNDARY` / `*CLOAD`: `MOD` (default) or
    /// `NEW` (only inside a step).
    pub(super) fn op_new(&self, line: usize, kw: &str, params: &Params) -> Result<bool, InpError> {
        let bad = |op: &str| InpError::Parameter {
            file: self.file.into(),
            line,
            keyword: kw.into(),
            parameter: format!("OP={op}"),
            valid: "OP=MOD, OP=NEW (inside *STEP)".into(),
        };
        match Self::param(params, "OP") {
            None => Ok(false),
            Some((_, None)) => Err(bad("")),
            Some((_, Some(op))) if op.eq_ignore_ascii_case("MOD") => Ok(false),
            Some((_, Some(op))) if op.eq_ignore_ascii_case("NEW") => {
                if self.step_open.is_none() {
                    return Err(self.invalid(
                        line,
                        kw,
                        "OP=NEW removes what earlier steps applied; it is only valid inside *STEP",
                    ));
                }
                Ok(true)
            }
            Some((_, Some(op))) => Err(bad(op)),
        }
    }

    /// Three finite numbers from `f[i..i + 3]`.
    pub(super) fn vector3(
        &self,
        line: usize,
        kw: &str,
        what: &str,
        f: &[&str],
    ) -> Result<[f64; 3], InpError> {
        let mut v = [0.0; 3];
        for (k, x) in v.iter_mut().enumerate() {
            *x = self.float(line, kw, what, f[k])?;
        }
        Ok(v)
    }
}
