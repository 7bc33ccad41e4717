//! Materials and sections: `*MATERIAL`, `*ELASTIC`, `*DENSITY`,
//! `*EXPANSION`, the `*DAMAGE ...` keywords of a cohesive material,
//! `*ORIENTATION`, `*SOLID SECTION` and `*COHESIVE SECTION`.

use super::*;

impl Parser<'_> {
    /// `*EXPANSION [, TYPE=ISO | ORTHO | ANISO] [, ZERO=]` ([`InpExpansion`]).
    pub(super) fn expansion(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "EXPANSION";
        self.check_params(line, kw, params, &["TYPE", "ZERO"])?;
        let Some(m) = &self.current_material else {
            return Err(self.invalid(line, kw, "*EXPANSION must follow *MATERIAL"));
        };
        if m.expansion.is_some() {
            return Err(self.invalid(
                line,
                kw,
                format!("material `{}` has two *EXPANSION", m.name),
            ));
        }
        let ty = Self::param(params, "TYPE")
            .and_then(|(_, v)| v.as_deref())
            .map(norm_key)
            .unwrap_or_else(|| "ISO".into());
        let names: &[&str] = match ty.as_str() {
            "ISO" | "ISOTROPIC" => &["alpha"],
            "ORTHO" | "ORTHOTROPIC" => &["alpha_11", "alpha_22", "alpha_33"],
            "ANISO" | "ANISOTROPIC" => &[
                "alpha_11", "alpha_22", "alpha_33", "alpha_12", "alpha_13", "alpha_23",
            ],
            _ => {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    parameter: format!("TYPE={ty}"),
                    valid: "TYPE=ISO, TYPE=ORTHO, TYPE=ANISO".into(),
                })
            }
        };
        let Some(&(dl, f, _)) = data.first() else {
            return Err(self.invalid(
                line,
                kw,
                format!("TYPE={ty} expects a data line with {}", names.join(", ")),
            ));
        };
        if let Some(&(d2, _, _)) = data.get(1) {
            return Err(self.invalid(
                d2,
                kw,
                "temperature-dependent expansion is not supported (one set of coefficients only)",
            ));
        }
        let values: Vec<&str> = f.iter().copied().filter(|s| !s.is_empty()).collect();
        if values.len() < names.len() || values.len() > names.len() + 1 {
            return Err(self.invalid(
                dl,
                kw,
                format!(
                    "TYPE={ty} expects {} value(s) ({}) and optionally the temperature, found {}",
                    names.len(),
                    names.join(", "),
                    values.len()
                ),
            ));
        }
        let mut v = Vec::with_capacity(names.len());
        for (name, t) in names.iter().zip(&values) {
            v.push(self.float(dl, kw, name, t)?);
        }
        if let Some(t) = values.get(names.len()) {
            let t = self.float(dl, kw, "temperature", t)?;
            self.deck.notes.push(format!(
                "line {dl}: *EXPANSION at temperature {t}: one set of coefficients, used at every temperature"
            ));
        }
        if let Some((_, z)) = Self::param(params, "ZERO") {
            let z = z.as_deref().unwrap_or("");
            self.float(line, kw, "ZERO", z)?;
            self.deck.notes.push(format!(
                "line {line}: *EXPANSION, ZERO={z}: with coefficients constant in temperature the thermal strain is alpha (T - T_initial) whatever the reference temperature"
            ));
        }
        let e = match v.len() {
            1 => InpExpansion::Isotropic(v[0]),
            3 => InpExpansion::Orthotropic([v[0], v[1], v[2]]),
            _ => InpExpansion::Anisotropic([v[0], v[1], v[2], v[3], v[4], v[5]]),
        };
        if let Some(m) = self.current_material.as_mut() {
            m.expansion = Some((e, dl));
        }
        Ok(())
    }

    pub(super) fn finish_material(&mut self) -> Result<(), InpError> {
        if let Some(m) = self.current_material.take() {
            let (name, line) = (m.name, m.line);
            let (kind, elastic_line) = m.elastic.ok_or_else(|| {
                self.invalid(
                    line,
                    "MATERIAL",
                    format!("material `{name}` has no *ELASTIC"),
                )
            })?;
            let damage =
                m.initiation.is_some() || m.evolution.is_some() || m.stabilization.is_some();
            if damage && !matches!(kind, InpMaterialKind::Traction(_)) {
                return Err(self.invalid(
                    line,
                    "MATERIAL",
                    format!("material `{name}` has damage options but its *ELASTIC is not TYPE=TRACTION: damage is read for cohesive materials (*ELASTIC, TYPE=TRACTION with *COHESIVE SECTION) only"),
                ));
            }
            if let (Some(i), None) = (&m.initiation, &m.evolution) {
                return Err(self.invalid(
                    i.line,
                    "DAMAGE INITIATION",
                    format!("material `{name}` has *DAMAGE INITIATION but no *DAMAGE EVOLUTION: Abaqus would then only report the initiation criterion and never soften (the stiffness stays K); add *DAMAGE EVOLUTION, TYPE=ENERGY with the fracture energies, or drop the damage keywords for a linear penalty"),
                ));
            }
            if let (Some(st), None) = (&m.stabilization, &m.initiation) {
                return Err(self.invalid(
                    st.line,
                    "DAMAGE STABILIZATION",
                    format!("material `{name}` has *DAMAGE STABILIZATION but no *DAMAGE INITIATION / *DAMAGE EVOLUTION: there is no damage to stabilise"),
                ));
            }
            self.material_index
                .insert(name.to_uppercase(), self.deck.materials.len());
            self.deck.materials.push(InpMaterial {
                name,
                kind,
                density: m.density,
                line,
                elastic_line,
                damage_initiation: m.initiation,
                damage_evolution: m.evolution,
                damage_stabilization: m.stabilization,
                expansion: m.expansion.map(|e| e.0),
            });
        }
        Ok(())
    }

    /// `*MATERIAL, NAME=`: opens a material; its options follow.
    pub(super) fn material(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "MATERIAL";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["NAME"])?;
        let name = self.required(line, kw, params, "NAME")?;
        if let Some(&m) = self.material_index.get(&name.to_uppercase()) {
            return Err(self.invalid(
                line,
                kw,
                format!(
                    "material `{name}` already defined at line {}",
                    self.deck.materials[m].line
                ),
            ));
        }
        if let Some(&(d, _, _)) = data.first() {
            return Err(self.invalid(d, kw, "*MATERIAL takes no data lines"));
        }
        self.current_material = Some(PendingMaterial {
            name,
            line,
            elastic: None,
            density: None,
            expansion: None,
            initiation: None,
            evolution: None,
            stabilization: None,
        });
        Ok(())
    }

    /// `*DENSITY`: kept on the material, noted as unused.
    pub(super) fn density(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DENSITY";
        self.check_params(line, kw, params, &[])?;
        if self.current_material.is_none() {
            return Err(self.invalid(line, kw, "*DENSITY must follow *MATERIAL"));
        }
        let (dl, f, _) = *data
            .first()
            .ok_or_else(|| self.invalid(line, kw, "expected a data line with the density"))?;
        let rho = self.float(dl, kw, "density", f.first().copied().unwrap_or(""))?;
        let name = self
            .current_material
            .as_ref()
            .map(|m| m.name.clone())
            .unwrap_or_default();
        if let Some(m) = self.current_material.as_mut() {
            m.density = Some(rho);
        }
        self.deck.notes.push(format!(
            "line {line}: *DENSITY of material `{name}` read but unused (static analysis)"
        ));
        Ok(())
    }

    /// Field `k` of a data line as a positive number (`None`: no line, or
    /// the field missing or empty).
    fn optional_positive(
        &self,
        data: Option<&(usize, &[&str], bool)>,
        k: usize,
        kw: &str,
        what: &str,
    ) -> Result<Option<f64>, InpError> {
        let Some((dl, f, _)) = data else {
            return Ok(None);
        };
        match f.get(k).filter(|t| !t.is_empty()) {
            None => Ok(None),
            Some(t) => {
                let v = self.float(*dl, kw, what, t)?;
                if !(v > 0.0 && v.is_finite()) {
                    return Err(self.invalid(
                        *dl,
                        kw,
                        format!(
                            "{what} {v} must be positive (leave the field empty for the default 1)"
                        ),
                    ));
                }
                Ok(Some(v))
            }
        }
    }

    /// `*SOLID SECTION, ELSET=, MATERIAL= [, ORIENTATION=]`, or `*SOLID
    /// SECTION, COMPOSITE, ELSET= [, ORIENTATION=] [, STACK DIRECTION=] [,
    /// LAYUP=]` with a data line per ply (resolved in
    /// [`Parser::assign_sections`]).
    pub(super) fn solid_section(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "SOLID SECTION";
        self.model_data_only(line, kw)?;
        self.check_params(
            line,
            kw,
            params,
            &[
                "ELSET",
                "MATERIAL",
                "ORIENTATION",
                "COMPOSITE",
                "STACK DIRECTION",
                "LAYUP",
                "OFFSET",
            ],
        )?;
        if let Some((_, Some(o))) = Self::param(params, "OFFSET") {
            let v = self.float(line, kw, "OFFSET", o)?;
            if v != 0.0 {
                return Err(self.invalid(
                    line,
                    kw,
                    format!("OFFSET={v}: Junta's plane elements lie on their mid-plane; only OFFSET=0 is supported"),
                ));
            }
        }
        let elset = self.required(line, kw, params, "ELSET")?;
        let orientation = match Self::param(params, "ORIENTATION") {
            None => None,
            Some(_) => Some(self.required(line, kw, params, "ORIENTATION")?),
        };
        if Self::param(params, "COMPOSITE").is_some() {
            let composite = self.composite_section(line, params, data)?;
            self.deck.solid_sections.push(InpSolidSection {
                elset,
                material: String::new(),
                orientation,
                thickness: None,
                composite: Some(composite),
                line,
            });
            return Ok(());
        }
        for p in ["STACK DIRECTION", "LAYUP"] {
            if Self::param(params, p).is_some() {
                return Err(self.invalid(
                    line,
                    kw,
                    format!("{p}= is a parameter of a composite section: add COMPOSITE (and a data line per ply), or remove it"),
                ));
            }
        }
        let material = self.required(line, kw, params, "MATERIAL")?;
        if data.len() > 1 {
            return Err(self.invalid(data[1].0, kw, "expected at most one data line"));
        }
        let thickness = self.optional_positive(data.first(), 0, kw, "thickness")?;
        self.deck.solid_sections.push(InpSolidSection {
            elset,
            material,
            orientation,
            thickness,
            composite: None,
            line,
        });
        Ok(())
    }

    /// The parameters and ply lines of `*SOLID SECTION, COMPOSITE`: each
    /// line `thickness, points (default 3), material, orientation name or
    /// angle (optional), ply name (optional)`.
    fn composite_section(
        &self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<InpComposite, InpError> {
        let kw = "SOLID SECTION";
        if let Some((_, Some(v))) = Self::param(params, "COMPOSITE") {
            return Err(self.bad_param(line, kw, format!("COMPOSITE={v}"), "COMPOSITE (no value)"));
        }
        if Self::param(params, "MATERIAL").is_some() {
            return Err(self.invalid(
                line,
                kw,
                "a composite section takes no MATERIAL=: each ply's data line names its material (`thickness, points, material, orientation, ply name`)",
            ));
        }
        let stack_direction = match Self::param(params, "STACK DIRECTION") {
            None => 3,
            Some((_, v)) => match v.as_deref().map(str::trim) {
                Some("1") => 1,
                Some("2") => 2,
                Some("3") => 3,
                v => {
                    return Err(self.bad_param(
                        line,
                        kw,
                        format!("STACK DIRECTION={}", v.unwrap_or("")),
                        "STACK DIRECTION=1, 2 or 3 (the element's natural direction the plies stack along; default 3); ORIENTATION is not supported",
                    ))
                }
            },
        };
        let layup = Self::param(params, "LAYUP").and_then(|(_, v)| v.clone());
        if data.is_empty() {
            return Err(self.invalid(
                line,
                kw,
                "a composite section needs a data line per ply, bottom to top: `thickness, number of integration points, material, orientation, ply name`",
            ));
        }
        let mut plies = Vec::with_capacity(data.len());
        for &(dl, f, _) in data {
            let field = |i: usize| f.get(i).map(|s| s.trim()).filter(|s| !s.is_empty());
            if f.len() > 5 {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!("a ply line has at most 5 fields (`thickness, number of integration points, material, orientation, ply name`), not {}", f.len()),
                ));
            }
            let t = field(0)
                .ok_or_else(|| self.invalid(dl, kw, "the ply's thickness (field 1) is missing"))?;
            let thickness = self.float(dl, kw, "ply thickness", t)?;
            if thickness <= 0.0 {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!("ply thickness {thickness} must be positive (thicknesses are relative: they are normalised to the element's thickness)"),
                ));
            }
            let points = match field(1) {
                None => 3,
                Some(n) => match n.parse::<usize>() {
                    Ok(n) if (1..=5).contains(&n) => n,
                    _ => {
                        return Err(InpError::BadNumber {
                            file: self.file.into(),
                            line: dl,
                            keyword: kw.into(),
                            what: "number of integration points through the ply".into(),
                            text: n.into(),
                            expected: "integer from 1 to 5 (default 3)",
                        })
                    }
                },
            };
            let material = field(2)
                .ok_or_else(|| {
                    self.invalid(
                        dl,
                        kw,
                        "the ply's material (field 3) is missing: `thickness, number of integration points, material, orientation, ply name`",
                    )
                })?
                .to_string();
            let axes = match field(3) {
                None => InpPlyAxes::Section,
                Some(o) => match o.replace(['d', 'D'], "e").parse::<f64>() {
                    Ok(a) if a.is_finite() => InpPlyAxes::Angle(a),
                    // a name: resolved with the other names
                    _ => InpPlyAxes::Named {
                        name: o.to_string(),
                        index: usize::MAX,
                    },
                },
            };
            plies.push(InpPly {
                thickness,
                points,
                material,
                axes,
                name: field(4).map(str::to_string),
                line: dl,
            });
        }
        Ok(InpComposite {
            stack_direction,
            layup,
            orientation: None,
            plies,
        })
    }

    /// `*COHESIVE SECTION, ELSET=, MATERIAL=, RESPONSE=TRACTION SEPARATION
    /// [, THICKNESS=SPECIFIED]`, data line: the constitutive thickness.
    pub(super) fn cohesive_section(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "COHESIVE SECTION";
        self.model_data_only(line, kw)?;
        self.check_params(
            line,
            kw,
            params,
            &["ELSET", "MATERIAL", "RESPONSE", "THICKNESS"],
        )?;
        let elset = self.required(line, kw, params, "ELSET")?;
        let material = self.required(line, kw, params, "MATERIAL")?;
        let response = norm_key(&self.required(line, kw, params, "RESPONSE")?);
        if response != "TRACTION SEPARATION" {
            return Err(InpError::Parameter {
                file: self.file.into(),
                line,
                keyword: kw.into(),
                parameter: format!("RESPONSE={response}"),
                valid: "RESPONSE=TRACTION SEPARATION".into(),
            });
        }
        match Self::param(params, "THICKNESS").map(|(_, v)| v.as_deref().map(norm_key)) {
            None => {}
            Some(Some(v)) if v == "SPECIFIED" => {}
            Some(v) => {
                return Err(self.bad_param(
                    line,
                    kw,
                    format!("THICKNESS={}", v.unwrap_or_default()),
                    "THICKNESS=SPECIFIED (the default: the constitutive thickness is the data line's, 1 when not given); GEOMETRY would take the element's geometric thickness, which is zero for Junta's interface elements",
                ))
            }
        }
        if data.len() > 1 {
            return Err(self.invalid(data[1].0, kw, "expected at most one data line"));
        }
        let thickness = match data.first() {
            Some((dl, f, _)) if !f.is_empty() && !f[0].is_empty() => {
                let t = self.float(*dl, kw, "initial thickness", f[0])?;
                if t <= 0.0 {
                    return Err(self.invalid(
                        *dl,
                        kw,
                        format!("constitutive thickness {t} must be positive (leave the field empty for the default 1)"),
                    ));
                }
                Some(t)
            }
            _ => None,
        };
        let out_of_plane = self.optional_positive(data.first(), 1, kw, "out-of-plane thickness")?;
        self.deck.cohesive_sections.push(InpCohesiveSection {
            elset,
            material,
            response,
            thickness,
            out_of_plane,
            line,
        });
        Ok(())
    }

    /// `*ELASTIC [, TYPE=]` of the current material: the constants of the
    /// type ([`Parser::elastic_type`], [`Parser::elastic_values`]); an
    /// orthotropic stiffness becomes engineering constants
    /// ([`Parser::ortho_to_engineering`]).
    pub(super) fn elastic(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "ELASTIC";
        self.check_params(line, kw, params, &["TYPE"])?;
        if self.current_material.is_none() {
            return Err(self.invalid(line, kw, "*ELASTIC must follow *MATERIAL"));
        }
        let ty = Self::param(params, "TYPE")
            .and_then(|(_, v)| v.as_deref())
            .map(norm_key)
            .unwrap_or_else(|| "ISOTROPIC".into());
        let (count, names) = self.elastic_type(line, &ty)?;
        // one set of constants at one temperature (`E, nu, T`): constant
        let lines_needed = count.div_ceil(8);
        let nonempty = |f: &[&str]| f.iter().filter(|s| !s.is_empty()).count();
        let total: usize = data.iter().take(lines_needed).map(|d| nonempty(d.1)).sum();
        let last: Vec<&str>;
        let mut data_vec: Vec<(usize, &[&str], bool)> = data.to_vec();
        if data.len() == lines_needed && total == count + 1 {
            let (dl, f, c) = data[lines_needed - 1];
            last = f.iter().copied().filter(|s| !s.is_empty()).collect();
            let t = self.float(dl, kw, "temperature", last[last.len() - 1])?;
            self.deck.notes.push(format!(
                "line {dl}: *ELASTIC at temperature {t}: one set of constants, used at every temperature"
            ));
            data_vec[lines_needed - 1] = (dl, &last[..last.len() - 1], c);
        }
        let data = &data_vec[..];
        let mut v = self.elastic_values(line, &ty, count, names, data)?;
        if ty == "ORTHO" || ty == "ORTHOTROPIC" {
            v = self.ortho_to_engineering(data[0].0, &v)?;
        }
        let kind = match count {
            2 => InpMaterialKind::Isotropic { e: v[0], nu: v[1] },
            3 => InpMaterialKind::Traction([v[0], v[1], v[2]]),
            21 => {
                let mut a = [0.0; 21];
                a.copy_from_slice(&v);
                InpMaterialKind::Anisotropic(Box::new(a))
            }
            _ => {
                let mut a = [0.0; 9];
                a.copy_from_slice(&v);
                InpMaterialKind::EngineeringConstants(a)
            }
        };
        if let Some(m) = &self.current_material {
            if m.elastic.is_some() {
                return Err(self.invalid(
                    line,
                    kw,
                    format!("material `{}` has two *ELASTIC", m.name),
                ));
            }
        }
        let data_line = data[0].0;
        if let Some(m) = self.current_material.as_mut() {
            m.elastic = Some((kind, data_line));
        }
        Ok(())
    }

    /// Number and names of the constants of `*ELASTIC, TYPE=ty`.
    pub(super) fn elastic_type(
        &self,
        line: usize,
        ty: &str,
    ) -> Result<(usize, &'static [&'static str]), InpError> {
        Ok(match ty {
            "ISOTROPIC" | "ISO" => (2, &["E", "nu"]),
            "ENGINEERING CONSTANTS" => (
                9,
                &[
                    "E1", "E2", "E3", "nu12", "nu13", "nu23", "G12", "G13", "G23",
                ],
            ),
            "TRACTION" => (3, &["K_nn", "K_ss", "K_tt"]),
            "ANISOTROPIC" | "ANISO" => (
                21,
                &[
                    "D1111", "D1122", "D2222", "D1133", "D2233", "D3333", "D1112", "D2212",
                    "D3312", "D1212", "D1113", "D2213", "D3313", "D1213", "D1313", "D1123",
                    "D2223", "D3323", "D1223", "D1323", "D2323",
                ],
            ),
            "ORTHOTROPIC" | "ORTHO" => (
                9,
                &[
                    "D1111", "D1122", "D2222", "D1133", "D2233", "D3333", "D1212", "D1313", "D2323",
                ],
            ),
            _ => {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: "ELASTIC".into(),
                    parameter: format!("TYPE={ty}"),
                    valid: "TYPE=ISOTROPIC, TYPE=ENGINEERING CONSTANTS, TYPE=ORTHO, TYPE=ANISO, TYPE=TRACTION"
                        .into(),
                })
            }
        })
    }

    /// The `count` constants (`names`) of `*ELASTIC, TYPE=ty`, 8 per data
    /// line (ENGINEERING CONSTANTS and ORTHO on 2 lines, ANISO on 3); more
    /// lines (temperature dependence) are refused.
    pub(super) fn elastic_values(
        &self,
        line: usize,
        ty: &str,
        count: usize,
        names: &[&str],
        data: &[(usize, &[&str], bool)],
    ) -> Result<Vec<f64>, InpError> {
        let kw = "ELASTIC";
        let lines_needed = count.div_ceil(8);
        if data.len() < lines_needed {
            return Err(self.invalid(
                line,
                kw,
                format!(
                    "TYPE={ty} expects {count} values ({}) on {lines_needed} data line(s)",
                    names.join(", ")
                ),
            ));
        }
        if data.len() > lines_needed {
            return Err(self.invalid(
                data[lines_needed].0,
                kw,
                "temperature-dependent elastic data is not supported (one set of constants only)",
            ));
        }
        let mut v = Vec::with_capacity(count);
        for &(dl, f, _) in &data[..lines_needed] {
            for t in f.iter().filter(|s| !s.is_empty()) {
                if v.len() == count {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!("too many values; TYPE={ty} expects {count} ({}); temperature is not supported", names.join(", ")),
                    ));
                }
                let name = names[v.len()];
                v.push(self.float(dl, kw, name, t)?);
            }
        }
        if v.len() != count {
            return Err(self.invalid(
                data[0].0,
                kw,
                format!(
                    "TYPE={ty} expects {count} values ({}), found {}",
                    names.join(", "),
                    v.len()
                ),
            ));
        }
        Ok(v)
    }

    /// Orthotropic stiffness `D1111 D1122 D2222 D1133 D2233 D3333 D1212
    /// D1313 D2323` -> engineering constants `E1 E2 E3 nu12 nu13 nu23 G12
    /// G13 G23`: `S` = inverse of the normal block [[D1111 D1122 D1133]
    /// [D1122 D2222 D2233] [D1133 D2233 D3333]]; `E_i = 1 / S_ii`, `nu_ij =
    /// -S_ij / S_ii` (`S_ij = -nu_ij / E_i`), `G_ij = D_ijij` (Abaqus
    /// Analysis User's Guide, "Linear elastic behavior", orthotropic
    /// `D_ijkl`). A stiffness that is not positive definite is refused
    /// (`data_line`).
    pub(super) fn ortho_to_engineering(
        &self,
        data_line: usize,
        v: &[f64],
    ) -> Result<Vec<f64>, InpError> {
        let d = [[v[0], v[1], v[3]], [v[1], v[2], v[4]], [v[3], v[4], v[5]]];
        let det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
            - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
            + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        let pos = d[0][0] > 0.0 && d[0][0] * d[1][1] - d[0][1] * d[0][1] > 0.0 && det > 0.0;
        if !(pos && v[6] > 0.0 && v[7] > 0.0 && v[8] > 0.0) {
            return Err(self.invalid(
                data_line,
                "ELASTIC",
                "TYPE=ORTHO: the stiffness is not positive definite",
            ));
        }
        let cof = |i: usize, j: usize| {
            let (r, c) = ([(i + 1) % 3, (i + 2) % 3], [(j + 1) % 3, (j + 2) % 3]);
            d[r[0]][c[0]] * d[r[1]][c[1]] - d[r[0]][c[1]] * d[r[1]][c[0]]
        };
        // symmetric: S_ij = cof(j, i) / det = cof(i, j) / det
        let sm = |i: usize, j: usize| cof(j, i) / det;
        let e = [1.0 / sm(0, 0), 1.0 / sm(1, 1), 1.0 / sm(2, 2)];
        let (g12, g13, g23) = (v[6], v[7], v[8]);
        Ok(vec![
            e[0],
            e[1],
            e[2],
            -sm(0, 1) / sm(0, 0),
            -sm(0, 2) / sm(0, 0),
            -sm(1, 2) / sm(1, 1),
            g12,
            g13,
            g23,
        ])
    }

    /// The material a damage keyword belongs to, or an error naming the
    /// line.
    pub(super) fn damage_material(
        &self,
        line: usize,
        kw: &str,
    ) -> Result<&PendingMaterial, InpError> {
        self.current_material.as_ref().ok_or_else(|| {
            self.invalid(
                line,
                kw,
                format!("*{kw} must follow the *MATERIAL (and its *ELASTIC, TYPE=TRACTION) of a cohesive material"),
            )
        })
    }

    /// The values of the single data line of a damage keyword: exactly
    /// `names.len()` numbers (temperature / field dependence is not read).
    pub(super) fn damage_values(
        &self,
        line: usize,
        kw: &str,
        what: &str,
        names: &[&str],
        data: &[(usize, &[&str], bool)],
    ) -> Result<(Vec<f64>, usize), InpError> {
        let expected = || {
            format!(
                "{what} expects one data line with {} value(s): {}",
                names.len(),
                names.join(", ")
            )
        };
        let Some(&(dl, f, _)) = data.first() else {
            return Err(self.invalid(line, kw, expected()));
        };
        if data.len() > 1 {
            return Err(self.invalid(
                data[1].0,
                kw,
                format!(
                    "{}; temperature- or field-dependent damage data is not supported",
                    expected()
                ),
            ));
        }
        let f: Vec<&str> = f.iter().copied().filter(|t| !t.is_empty()).collect();
        if f.len() > names.len() {
            return Err(self.invalid(
                dl,
                kw,
                format!(
                    "{}, found {}; temperature- or field-dependent damage data is not supported",
                    expected(),
                    f.len()
                ),
            ));
        }
        if f.len() < names.len() {
            return Err(self.invalid(dl, kw, format!("{}, found {}", expected(), f.len())));
        }
        let mut v = Vec::with_capacity(f.len());
        for (t, name) in f.iter().zip(names) {
            let x = self.float(dl, kw, name, t)?;
            if x < 0.0 {
                return Err(self.invalid(dl, kw, format!("{name} = {x} must not be negative")));
            }
            v.push(x);
        }
        Ok((v, dl))
    }

    /// `*DAMAGE INITIATION, CRITERION=QUADS | MAXS`.
    pub(super) fn damage_initiation(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DAMAGE INITIATION";
        let m = self.damage_material(line, kw)?;
        if let Some(i) = &m.initiation {
            return Err(self.invalid(
                line,
                kw,
                format!("material `{}` already has a *DAMAGE INITIATION at line {}; Junta reads one criterion per cohesive material", m.name, i.line),
            ));
        }
        self.check_params(line, kw, params, &["CRITERION"])?;
        let valid = "CRITERION=QUADS, CRITERION=MAXS (cohesive nominal-stress criteria)";
        let criterion = match norm_key(&self.required(line, kw, params, "CRITERION")?).as_str() {
            "QUADS" => InpOnset::Quads,
            "MAXS" => InpOnset::Maxs,
            other => return Err(self.bad_param(line, kw, format!("CRITERION={other}"), valid)),
        };
        let (v, data_line) = self.damage_values(
            line,
            kw,
            "the criterion",
            &[
                "t_n^0 (normal strength)",
                "t_s^0 (first shear strength)",
                "t_t^0 (second shear strength)",
            ],
            data,
        )?;
        if let Some(k) = v.iter().position(|&x| x <= 0.0) {
            return Err(self.invalid(
                data_line,
                kw,
                format!(
                    "strength {} must be positive",
                    ["t_n^0", "t_s^0", "t_t^0"][k]
                ),
            ));
        }
        if let Some(m) = self.current_material.as_mut() {
            m.initiation = Some(InpDamageInitiation {
                criterion,
                strengths: [v[0], v[1], v[2]],
                line,
                data_line,
            });
        }
        Ok(())
    }

    /// `*DAMAGE EVOLUTION, TYPE=ENERGY [, SOFTENING=] [, MIXED MODE
    /// BEHAVIOR=, POWER=]`: softening ([`Parser::evolution_softening`]),
    /// mixed-mode rule ([`Parser::evolution_mixed_mode`]) and the fracture
    /// energies of the data line.
    pub(super) fn damage_evolution(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DAMAGE EVOLUTION";
        let m = self.damage_material(line, kw)?;
        if m.initiation.is_none() {
            return Err(self.invalid(
                line,
                kw,
                format!("*DAMAGE EVOLUTION of material `{}` must follow its *DAMAGE INITIATION (it is a sub-option of it)", m.name),
            ));
        }
        if let Some(e) = &m.evolution {
            return Err(self.invalid(
                line,
                kw,
                format!(
                    "material `{}` already has a *DAMAGE EVOLUTION at line {}",
                    m.name, e.line
                ),
            ));
        }
        self.check_params(
            line,
            kw,
            params,
            &[
                "TYPE",
                "SOFTENING",
                "MIXED MODE BEHAVIOR",
                "POWER",
                "DEGRADATION",
            ],
        )?;
        let softening = self.evolution_softening(line, params)?;
        let mixed_mode = self.evolution_mixed_mode(line, params)?;
        let (toughness, data_line) = if mixed_mode == InpMixedMode::ModeIndependent {
            let (v, dl) = self.damage_values(
                line,
                kw,
                "MODE INDEPENDENT",
                &["G_c (fracture energy)"],
                data,
            )?;
            ([v[0]; 3], dl)
        } else {
            let (v, dl) = self.damage_values(
                line,
                kw,
                "a mixed-mode rule",
                &[
                    "G_Ic (normal mode fracture energy)",
                    "G_IIc (first shear)",
                    "G_IIIc (second shear)",
                ],
                data,
            )?;
            ([v[0], v[1], v[2]], dl)
        };
        if let Some(k) = toughness.iter().position(|&x| x <= 0.0) {
            return Err(self.invalid(
                data_line,
                kw,
                format!(
                    "fracture energy {} must be positive",
                    ["G_Ic", "G_IIc", "G_IIIc"][k]
                ),
            ));
        }
        if let Some(m) = self.current_material.as_mut() {
            m.evolution = Some(InpDamageEvolution {
                softening,
                mixed_mode,
                toughness,
                line,
                data_line,
            });
        }
        Ok(())
    }

    /// `TYPE=ENERGY` (required), `SOFTENING=LINEAR | EXPONENTIAL` and
    /// `DEGRADATION=MAXIMUM` of `*DAMAGE EVOLUTION`.
    pub(super) fn evolution_softening(
        &self,
        line: usize,
        params: &Params,
    ) -> Result<InpSoftening, InpError> {
        let kw = "DAMAGE EVOLUTION";
        match norm_key(&self.required(line, kw, params, "TYPE")?).as_str() {
            "ENERGY" => {}
            other => {
                return Err(self.bad_param(
                    line,
                    kw,
                    format!("TYPE={other}"),
                    "TYPE=ENERGY (fracture energies; TYPE=DISPLACEMENT is not supported)",
                ))
            }
        }
        let softening =
            match Self::param(params, "SOFTENING").map(|(_, v)| v.as_deref().map(norm_key)) {
                None => InpSoftening::Linear,
                Some(Some(v)) if v == "LINEAR" => InpSoftening::Linear,
                Some(Some(v)) if v == "EXPONENTIAL" => InpSoftening::Exponential,
                Some(v) => return Err(self.bad_param(
                    line,
                    kw,
                    format!("SOFTENING={}", v.unwrap_or_default()),
                    "SOFTENING=LINEAR (default), SOFTENING=EXPONENTIAL (TABULAR is not supported)",
                )),
            };
        match Self::param(params, "DEGRADATION").map(|(_, v)| v.as_deref().map(norm_key)) {
            None => {}
            Some(Some(v)) if v == "MAXIMUM" => {}
            Some(v) => {
                return Err(self.bad_param(
                    line,
                    kw,
                    format!("DEGRADATION={}", v.unwrap_or_default()),
                    "DEGRADATION=MAXIMUM (the default; one damage mechanism per material)",
                ))
            }
        }
        Ok(softening)
    }

    /// `MIXED MODE BEHAVIOR=MODE INDEPENDENT | BK | POWER LAW` of `*DAMAGE
    /// EVOLUTION`, with the exponent `POWER=` that BK and POWER LAW need
    /// (and MODE INDEPENDENT refuses).
    pub(super) fn evolution_mixed_mode(
        &self,
        line: usize,
        params: &Params,
    ) -> Result<InpMixedMode, InpError> {
        let kw = "DAMAGE EVOLUTION";
        let power = match Self::param(params, "POWER") {
            None => None,
            Some((_, Some(v))) => {
                let p = self.float(line, kw, "POWER", v)?;
                if p <= 0.0 {
                    return Err(self.invalid(line, kw, format!("POWER={p} must be positive")));
                }
                Some(p)
            }
            Some((_, None)) => {
                return Err(self.invalid(line, kw, "POWER needs a value, e.g. POWER=2.284"))
            }
        };
        let mixed = Self::param(params, "MIXED MODE BEHAVIOR")
            .map(|(_, v)| v.as_deref().map(norm_key).unwrap_or_default());
        let need_power = |what: &str| {
            self.invalid(
                line,
                kw,
                format!("MIXED MODE BEHAVIOR={what} needs POWER= (the exponent of the rule)"),
            )
        };
        Ok(match mixed.as_deref() {
            None | Some("MODE INDEPENDENT") => {
                if power.is_some() {
                    return Err(self.invalid(
                        line,
                        kw,
                        "POWER= is only used with MIXED MODE BEHAVIOR=BK or POWER LAW",
                    ));
                }
                InpMixedMode::ModeIndependent
            }
            Some("BK") => InpMixedMode::Bk {
                power: power.ok_or_else(|| need_power("BK"))?,
            },
            Some("POWER LAW") => InpMixedMode::PowerLaw {
                power: power.ok_or_else(|| need_power("POWER LAW"))?,
            },
            Some(other) => {
                return Err(self.bad_param(
                    line,
                    kw,
                    format!("MIXED MODE BEHAVIOR={other}"),
                    "MIXED MODE BEHAVIOR=MODE INDEPENDENT (default), BK, POWER LAW (TABULAR is not supported)",
                ))
            }
        })
    }

    /// `*DAMAGE STABILIZATION`: one viscosity coefficient.
    pub(super) fn damage_stabilization(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "DAMAGE STABILIZATION";
        let m = self.damage_material(line, kw)?;
        if let Some(st) = &m.stabilization {
            return Err(self.invalid(
                line,
                kw,
                format!(
                    "material `{}` already has a *DAMAGE STABILIZATION at line {}",
                    m.name, st.line
                ),
            ));
        }
        self.check_params(line, kw, params, &[])?;
        let (v, _) = self.damage_values(
            line,
            kw,
            "*DAMAGE STABILIZATION",
            &["viscosity coefficient"],
            data,
        )?;
        if let Some(m) = self.current_material.as_mut() {
            m.stabilization = Some(InpDamageStabilization {
                viscosity: v[0],
                line,
            });
        }
        Ok(())
    }

    /// `*ORIENTATION, NAME= [, SYSTEM=RECTANGULAR|CYLINDRICAL] [, DEFINITION=COORDINATES]`:
    /// rectangular `a, b [, c]` (points: a on material axis 1, b in the 1-2
    /// plane, c the origin); cylindrical `a, b` (two points of the axis,
    /// exactly 6 values); an optional second line `axis, angle` must have
    /// angle 0.
    pub(super) fn orientation(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "ORIENTATION";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["NAME", "SYSTEM", "DEFINITION"])?;
        let name = self.required(line, kw, params, "NAME")?;
        let value = |k: &str| {
            Self::param(params, k)
                .and_then(|(_, v)| v.as_deref())
                .map(norm_key)
        };
        let cylindrical = match value("SYSTEM").as_deref() {
            None | Some("RECTANGULAR") | Some("R") => false,
            Some("CYLINDRICAL") | Some("C") => true,
            Some(sys) => {
                return Err(InpError::Parameter {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    parameter: format!("SYSTEM={sys}"),
                    valid: "SYSTEM=RECTANGULAR or SYSTEM=CYLINDRICAL".into(),
                })
            }
        };
        if let Some(d) = value("DEFINITION").filter(|d| d != "COORDINATES") {
            return Err(InpError::Parameter {
                file: self.file.into(),
                line,
                keyword: kw.into(),
                parameter: format!("DEFINITION={d}"),
                valid: "DEFINITION=COORDINATES".into(),
            });
        }
        let expected = if cylindrical {
            "`ax, ay, az, bx, by, bz` (two points a, b of the cylinder axis)"
        } else {
            "`ax, ay, az, bx, by, bz [, cx, cy, cz]`"
        };
        let Some(&(dl, f, _)) = data.first() else {
            return Err(self.invalid(line, kw, format!("expected a data line {expected}")));
        };
        let f: Vec<&str> = f.iter().copied().filter(|t| !t.is_empty()).collect();
        if !(f.len() == 6 || (f.len() == 9 && !cylindrical)) {
            return Err(self.invalid(
                dl,
                kw,
                format!(
                    "expected {} values {expected}, found {}",
                    if cylindrical { "6" } else { "6 or 9" },
                    f.len()
                ),
            ));
        }
        let a = self.vector3(dl, kw, "point a", &f[0..3])?;
        let b = self.vector3(dl, kw, "point b", &f[3..6])?;
        let c = if f.len() == 9 {
            self.deck.notes.push(format!(
                "{}:{dl}: *ORIENTATION {name}: origin c (values 7-9) used as in Abaqus, material axis 1 along a - c; CalculiX 2.20 ignores these values",
                self.file
            ));
            self.vector3(dl, kw, "origin c", &f[6..9])?
        } else {
            [0.0; 3]
        };
        if let Some(&(l2, f2, _)) = data.get(1) {
            let angle = match f2.get(1) {
                Some(t) => self.float(l2, kw, "rotation angle", t)?,
                None => 0.0,
            };
            if angle != 0.0 || data.len() > 2 {
                return Err(self.invalid(
                    l2,
                    kw,
                    "an additional rotation about a local axis (second data line with a non-zero angle) is not supported",
                ));
            }
        }
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let (a, b) = if cylindrical {
            // the axis direction b - a, relative to the points' size
            if norm(sub(b, a)) <= 1e-12 * norm(a).max(norm(b)) {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!(
                        "cylindrical system: points a = {a:?} and b = {b:?} must differ (they give the cylinder axis)"
                    ),
                ));
            }
            (a, b)
        } else {
            let (a, b) = (sub(a, c), sub(b, c));
            let cross = [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ];
            if norm(a) == 0.0 || norm(cross) <= 1e-10 * norm(a) * norm(b) {
                return Err(self.invalid(
                    dl,
                    kw,
                    "point a must differ from the origin and point b must not lie on the line through the origin and a",
                ));
            }
            (a, b)
        };
        if self
            .deck
            .orientations
            .iter()
            .any(|o| o.name.eq_ignore_ascii_case(&name))
        {
            return Err(self.invalid(line, kw, format!("orientation `{name}` is defined twice")));
        }
        self.deck.orientations.push(InpOrientation {
            name,
            a,
            b,
            cylindrical,
            line,
        });
        Ok(())
    }
}
