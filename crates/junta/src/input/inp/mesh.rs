//! The mesh of a deck: `*NODE`, `*ELEMENT`, `*NSET`/`*ELSET`, `*SURFACE`,
//! element targets and `*MEMBRANE`.

use super::*;

impl Parser<'_> {
    /// `*MEMBRANE, ELSET=, MATERIAL=`: accepted on an element set without
    /// elements (CalculiX's test decks carry such lines), refused otherwise
    /// (checked when the sets are complete).
    pub(super) fn membrane(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "MEMBRANE";
        self.check_params(line, kw, params, &["ELSET", "MATERIAL", "ORIENTATION"])?;
        self.model_data_only(line, kw)?;
        let elset = self.required(line, kw, params, "ELSET")?;
        if data.len() > 1 {
            return Err(self.invalid(data[1].0, kw, "expected one data line (the thickness)"));
        }
        self.membranes.push((line, elset));
        Ok(())
    }

    pub(super) fn node(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "NODE";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["NSET"])?;
        let set = match Self::param(params, "NSET") {
            Some(_) => {
                let name = self.required(line, kw, params, "NSET")?;
                Some(Self::set_mut(&mut self.nsets, &mut self.nset_index, &name))
            }
            None => None,
        };
        for &(dl, f, _) in data {
            let f: Vec<&str> = f.iter().copied().filter(|s| !s.is_empty()).collect();
            if f.is_empty() || f.len() > 4 {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!(
                        "expected `label, x[, y[, z]]` (a missing coordinate is 0), found {} values",
                        f.len()
                    ),
                ));
            }
            let label = self.label(dl, kw, "node label", f[0])?;
            let mut x = [0.0; 3];
            for (d, t) in f[1..].iter().enumerate() {
                x[d] = self.float(dl, kw, ["x", "y", "z"][d], t)?;
            }
            if self.node_id.contains_key(&label) {
                return Err(self.invalid(dl, kw, format!("node label {label} defined twice")));
            }
            let id = self.nodes.len();
            self.node_id.insert(label, id);
            self.nodes.push(x);
            self.labels.push(label);
            if let Some(s) = set {
                self.nsets[s].members.push(id);
            }
        }
        Ok(())
    }

    pub(super) fn element(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "ELEMENT";
        self.model_data_only(line, kw)?;
        self.check_params(line, kw, params, &["TYPE", "ELSET"])?;
        let type_name = self.required(line, kw, params, "TYPE")?.to_uppercase();
        let (shape, etype) = element_kind(&type_name).ok_or_else(|| InpError::ElementType {
            file: self.file.into(),
            line,
            element_type: type_name.clone(),
            valid: SUPPORTED_ELEMENT_TYPES.into(),
        })?;
        let elset = match Self::param(params, "ELSET") {
            Some(_) => Some(self.required(line, kw, params, "ELSET")?),
            None => None,
        };
        let key = (
            type_name.clone(),
            elset.as_deref().unwrap_or("").to_uppercase(),
        );
        let pb = match self.pre_block_key.get(&key) {
            Some(&b) => b,
            None => {
                let base = elset.clone().unwrap_or_else(|| type_name.to_lowercase());
                let name = if self.pre_blocks.iter().any(|b| b.name == base) {
                    format!("{base}_{}", type_name.to_lowercase())
                } else {
                    base
                };
                self.pre_blocks.push(PreBlock {
                    name,
                    shape,
                    element_type: etype,
                });
                self.pre_block_key.insert(key, self.pre_blocks.len() - 1);
                self.pre_blocks.len() - 1
            }
        };
        let set = elset
            .as_deref()
            .map(|e| Self::set_mut(&mut self.elsets, &mut self.elset_index, e));
        let n = shape.num_nodes();
        let mut k = 0;
        while k < data.len() {
            let (dl, first, mut cont) = data[k];
            let mut fields: Vec<&str> = first.to_vec();
            let mut full16 = first.len() + usize::from(cont) >= 16;
            k += 1;
            while fields.len() < n + 1 && (cont || full16) && k < data.len() {
                let (_, more, c) = data[k];
                fields.extend_from_slice(more);
                cont = c;
                full16 = more.len() + usize::from(c) >= 16;
                k += 1;
            }
            let fields: Vec<&str> = fields.into_iter().filter(|s| !s.is_empty()).collect();
            if fields.is_empty() {
                continue;
            }
            let label = self.label(dl, kw, "element label", fields[0])?;
            if fields.len() != n + 1 {
                return Err(self.invalid(
                    dl,
                    kw,
                    format!(
                        "element {label}: TYPE={type_name} needs {n} nodes, found {} (a long element line continues on the next line when it ends with a comma)",
                        fields.len() - 1
                    ),
                ));
            }
            let mut given = Vec::with_capacity(n);
            for t in &fields[1..] {
                let l = self.label(dl, kw, "node label", t)?;
                given.push(self.node_of(dl, kw, l)?);
            }
            let conn: Vec<usize> = match shape {
                CellShape::Hex27 => C3D27_TO_OURS.iter().map(|&a| given[a]).collect(),
                // COH2D4 1-2-3-4 counter-clockwise (the top on the left of
                // 1-2): ours has the top on the right of the bottom line
                CellShape::LineInter4 => vec![given[1], given[0], given[2], given[3]],
                _ => given,
            };
            if self.elem_id.contains_key(&label) {
                return Err(self.invalid(dl, kw, format!("element label {label} defined twice")));
            }
            let id = self.elems.len();
            self.elem_id.insert(label, id);
            self.elems.push(Elem {
                pre_block: pb,
                conn,
                label,
                material: None,
                orientation: None,
                thickness: None,
            });
            if let Some(s) = set {
                self.elsets[s].members.push(id);
            }
        }
        Ok(())
    }

    pub(super) fn set(
        &mut self,
        line: usize,
        kw: &str,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        self.model_data_only(line, kw)?;
        let is_node = kw == "NSET";
        self.check_params(line, kw, params, &[kw, "GENERATE"])?;
        let name = self.required(line, kw, params, kw)?;
        let generate = Self::param(params, "GENERATE").is_some();
        let mut members = Vec::new();
        for &(dl, f, _) in data {
            let f: Vec<&str> = f.iter().copied().filter(|s| !s.is_empty()).collect();
            if generate {
                if f.len() < 2 || f.len() > 3 {
                    return Err(self.invalid(
                        dl,
                        kw,
                        "GENERATE expects `first, last[, increment]`",
                    ));
                }
                let a = self.label(dl, kw, "first label", f[0])?;
                let b = self.label(dl, kw, "last label", f[1])?;
                let inc = if f.len() == 3 {
                    self.label(dl, kw, "increment", f[2])?
                } else {
                    1
                };
                if b < a {
                    return Err(self.invalid(
                        dl,
                        kw,
                        format!("GENERATE range {a}..{b} is empty (last < first)"),
                    ));
                }
                if inc == 0 {
                    return Err(self.invalid(dl, kw, "GENERATE increment must be >= 1"));
                }
                // labels missing inside a range are skipped, as gaps are common;
                // a range wider than the labels defined walks the labels
                // instead (bounded by the deck, not by the range: 1..1e11 is quick)
                let map = if is_node {
                    &self.node_id
                } else {
                    &self.elem_id
                };
                if (b - a) / inc >= map.len() {
                    let mut hits: Vec<(usize, usize)> = map
                        .iter()
                        .filter(|(&l, _)| l >= a && l <= b && (l - a) % inc == 0)
                        .map(|(&l, &id)| (l, id))
                        .collect();
                    hits.sort_unstable();
                    members.extend(hits.into_iter().map(|h| h.1));
                } else {
                    for l in (a..=b).step_by(inc) {
                        if let Some(&id) = map.get(&l) {
                            members.push(id);
                        }
                    }
                }
            } else {
                for t in f {
                    // a label or a set name, as every other target
                    if is_node {
                        members.extend(self.node_target(dl, kw, t)?);
                    } else {
                        members.extend(self.element_target(dl, kw, t)?);
                    }
                }
            }
        }
        let s = if is_node {
            Self::set_mut(&mut self.nsets, &mut self.nset_index, &name)
        } else {
            Self::set_mut(&mut self.elsets, &mut self.elset_index, &name)
        };
        let target = if is_node {
            &mut self.nsets[s]
        } else {
            &mut self.elsets[s]
        };
        target.members.extend(members);
        Ok(())
    }

    /// `*SURFACE, NAME= [, TYPE=ELEMENT|NODE]`: element faces
    /// (`element or elset, S1..S6` or `P1..P6`) or nodes (`node or nset [, weight]`).
    pub(super) fn surface(
        &mut self,
        line: usize,
        params: &Params,
        data: &[(usize, &[&str], bool)],
    ) -> Result<(), InpError> {
        let kw = "SURFACE";
        self.check_params(line, kw, params, &["NAME", "TYPE"])?;
        let name = self.required(line, kw, params, "NAME")?;
        let node = self.two_way(
            line,
            kw,
            params,
            ("TYPE", "ELEMENT", "NODE"),
            "TYPE=ELEMENT (faces S1..S6, the default), TYPE=NODE",
        )?;
        if data.is_empty() {
            return Err(self.invalid(line, kw, format!("surface `{name}` has no data lines")));
        }
        let key = name.to_uppercase();
        if node {
            let mut nodes = Vec::new();
            for &(dl, f, _) in data {
                if f.is_empty() || f[0].is_empty() || f.len() > 2 {
                    return Err(self.invalid(dl, kw, "expected `node or node set [, weight]`"));
                }
                nodes.extend(self.node_target(dl, kw, f[0])?);
            }
            nodes.sort_unstable();
            nodes.dedup();
            self.deck
                .node_surfaces
                .entry(key)
                .or_default()
                .extend(nodes);
            return Ok(());
        }
        let mut faces = Vec::with_capacity(data.len());
        for &(dl, f, _) in data {
            if f.len() != 2 || f[0].is_empty() {
                return Err(self.invalid(
                    dl,
                    kw,
                    "expected `element or element set, face` with the face S1..S6",
                ));
            }
            // S1..S6 (Abaqus) or P1..P6 (CalculiX's *DLOAD face names)
            let letter = if f[1].trim().to_uppercase().starts_with('P') {
                'P'
            } else {
                'S'
            };
            let face = self.face_label(dl, kw, f[1], letter)?;
            faces.push((f[0].to_string(), face));
        }
        self.surfaces
            .entry(key)
            .or_insert_with(|| (line, Vec::new()))
            .1
            .extend(faces);
        Ok(())
    }

    /// Face `S1`..`S6` (or `P1`..`P6` with `letter = 'P'`), 0-based.
    pub(super) fn face_label(
        &self,
        line: usize,
        kw: &str,
        text: &str,
        letter: char,
    ) -> Result<usize, InpError> {
        let t = text.trim().to_uppercase();
        match t.strip_prefix(letter).and_then(|n| n.parse::<usize>().ok()) {
            Some(n @ 1..=6) => Ok(n - 1),
            _ => Err(self.invalid(
                line,
                kw,
                format!(
                    "face `{text}`: valid faces are {letter}1..{letter}6 (solid element faces)"
                ),
            )),
        }
    }

    /// Flat element ids of an element label or element set.
    pub(super) fn element_target(
        &self,
        line: usize,
        kw: &str,
        target: &str,
    ) -> Result<Vec<usize>, InpError> {
        if target.chars().all(|c| c.is_ascii_digit()) {
            let l = self.label(line, kw, "element label", target)?;
            let id = self
                .elem_id
                .get(&l)
                .copied()
                .ok_or_else(|| InpError::UndefinedLabel {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    kind: "element",
                    label: l,
                })?;
            Ok(vec![id])
        } else {
            match self.elset_index.get(&target.to_uppercase()) {
                Some(&s) => Ok(self.elsets[s].members.clone()),
                None => Err(self.unknown_set(line, kw, "element set", target)),
            }
        }
    }
}
