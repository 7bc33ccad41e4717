//! Resolution once every line is read: sections assigned to elements,
//! amplitudes, distributed loads and equations bound to their targets, the
//! element blocks built, and the [`InpDeck`] returned.

use super::*;

impl Parser<'_> {
    /// Resolve the targets of the distributed loads to `(flat element id,
    /// face)` lists (the flat ids become element references in `finish`),
    /// checking that a pressure's face exists on the element.
    pub(super) fn resolve_dloads(&mut self) -> Result<Vec<Vec<(usize, usize)>>, InpError> {
        let targets = std::mem::take(&mut self.dload_targets);
        let mut out = Vec::with_capacity(targets.len());
        for (k, t) in targets.iter().enumerate() {
            let (line, pressure) = (
                self.deck.dloads[k].line,
                matches!(self.deck.dloads[k].kind, InpDloadKind::Pressure(_)),
            );
            let kw = if matches!(t, DloadTarget::Surface(_)) {
                "DSLOAD"
            } else {
                "DLOAD"
            };
            let mut list = Vec::new();
            // where the faces were written: the *SURFACE's keyword line
            let mut surface_at = None;
            match t {
                DloadTarget::Elements { target, face } => {
                    for e in self.element_target(line, kw, target)? {
                        list.push((e, *face));
                    }
                }
                DloadTarget::Surface(name) => {
                    let key = name.to_uppercase();
                    let Some((_, faces)) = self.surfaces.get(&key) else {
                        let what = if self.deck.node_surfaces.contains_key(&key) {
                            format!("`{name}` is a node surface (TYPE=NODE); a pressure needs an element surface (TYPE=ELEMENT, faces S1..S6)")
                        } else {
                            let mut names: Vec<&String> = self.surfaces.keys().collect();
                            names.sort();
                            format!("element surface `{name}` is not defined; defined: {names:?}")
                        };
                        return Err(self.invalid(line, kw, what));
                    };
                    surface_at = Some((name, self.surfaces[&key].0));
                    for (target, face) in faces {
                        for e in self.element_target(line, kw, target)? {
                            list.push((e, *face));
                        }
                    }
                }
            }
            for &(e, face) in &list {
                let el = &self.elems[e];
                let shape = self.pre_blocks[el.pre_block].shape;
                if !shape.is_solid() {
                    return Err(self.invalid(
                        line,
                        kw,
                        format!(
                            "element {} is a {} element; distributed loads act on solids",
                            el.label,
                            shape.name()
                        ),
                    ));
                }
                if pressure && face >= shape.num_faces() {
                    let n = shape.num_faces();
                    let written = match &surface_at {
                        Some((name, at)) => {
                            format!("face S{} of surface `{name}` (line {at})", face + 1)
                        }
                        None => format!("P{}", face + 1),
                    };
                    return Err(self.invalid(
                        line,
                        kw,
                        format!(
                            "{written}: element {} is a {} element, whose faces are P1..P{n} (S1..S{n})",
                            el.label,
                            shape.name()
                        ),
                    ));
                }
            }
            out.push(list);
        }
        Ok(out)
    }

    /// Resolve the terms of the `*EQUATION`s: a node set stands for each of
    /// its members in turn (every set of one equation must have as many).
    pub(super) fn resolve_equations(&mut self) -> Result<(), InpError> {
        let kw = "EQUATION";
        let written = std::mem::take(&mut self.equation_terms);
        for (line, terms) in &written {
            let mut nodes = Vec::with_capacity(terms.len());
            let mut count = 1;
            for (target, _, _) in terms {
                let ns = self.node_target(*line, kw, target)?;
                if ns.is_empty() {
                    return Err(self.invalid(*line, kw, format!("node set `{target}` is empty")));
                }
                if ns.len() != 1 {
                    if count != 1 && ns.len() != count {
                        return Err(self.invalid(
                            *line,
                            kw,
                            format!(
                                "node set `{target}` has {} nodes but another set of the equation has {count}; sets of one equation must have as many nodes",
                                ns.len()
                            ),
                        ));
                    }
                    count = ns.len();
                }
                nodes.push(ns);
            }
            for i in 0..count {
                let terms = terms
                    .iter()
                    .zip(&nodes)
                    .map(|((_, dof, a), ns)| (if ns.len() == 1 { ns[0] } else { ns[i] }, *dof, *a))
                    .collect();
                self.deck.equations.push(InpEquation { terms, line: *line });
            }
        }
        Ok(())
    }

    /// Resolve targets, assign sections, build the mesh: the `*EQUATION`
    /// terms, the `AMPLITUDE=` names, the distributed loads' elements, the
    /// boundary and load nodes, the sections ([`Parser::assign_sections`]),
    /// the use of damage materials, the curve directive, then the blocks
    /// ([`Parser::build_blocks`]) and the mesh with its sets
    /// ([`Parser::into_deck`]).
    pub(super) fn finish(mut self) -> Result<InpDeck, InpError> {
        self.resolve_equations()?;
        self.resolve_amplitudes()?;
        let dload_ids = self.resolve_dloads()?;
        for (k, p) in self.boundary_targets.iter().enumerate() {
            self.deck.boundaries[k].nodes = self.node_target(p.line, p.keyword, &p.target)?;
        }
        for (k, p) in self.cload_targets.iter().enumerate() {
            self.deck.cloads[k].nodes = self.node_target(p.line, p.keyword, &p.target)?;
        }
        for k in 0..self.deck.temperatures.len() {
            let t = &self.deck.temperatures[k];
            let kw = if t.step.is_some() {
                "TEMPERATURE"
            } else {
                "INITIAL CONDITIONS"
            };
            self.deck.temperatures[k].nodes = self.node_target(t.line, kw, &t.target)?;
        }
        for &(line, ref elset) in &self.membranes {
            let members = self
                .elset_index
                .get(&elset.to_uppercase())
                .map_or(0, |&i| self.elsets[i].members.len());
            if members > 0 {
                return Err(self.invalid(
                    line,
                    "MEMBRANE",
                    format!("ELSET={elset} has {members} element(s): membrane elements are not supported (Junta's elements are solids and interfaces)"),
                ));
            }
            self.deck.notes.push(format!(
                "line {line}: *MEMBRANE, ELSET={elset} ignored: the set has no elements"
            ));
        }
        self.assign_sections()?;
        for m in self.deck.materials.iter().filter(|m| m.has_damage()) {
            if !self
                .deck
                .cohesive_sections
                .iter()
                .any(|c| c.material.eq_ignore_ascii_case(&m.name))
            {
                return Err(self.invalid(
                    m.line,
                    "MATERIAL",
                    format!("material `{}` has damage options but no *COHESIVE SECTION uses it: damage is read for cohesive elements (COH3D8, COH3D6) only", m.name),
                ));
            }
        }
        self.resolve_curve()?;
        let (refs, blocks, block_orientations) = self.build_blocks();
        self.deck.block_composites = blocks
            .iter()
            .map(|b| {
                self.deck
                    .solid_sections
                    .iter()
                    .position(|s| s.composite.is_some() && s.block_material() == b.material)
            })
            .collect();
        self.into_deck(refs, blocks, block_orientations, dload_ids)
    }

    /// Each `AMPLITUDE=` name to the index of its `*AMPLITUDE`.
    pub(super) fn resolve_amplitudes(&mut self) -> Result<(), InpError> {
        for (what, k, name, line) in std::mem::take(&mut self.amplitude_refs) {
            let Some(a) = self
                .deck
                .amplitudes
                .iter()
                .position(|a| a.name.eq_ignore_ascii_case(&name))
            else {
                let kw = match what {
                    AmplitudeUse::Boundary => "BOUNDARY",
                    AmplitudeUse::Cload => "CLOAD",
                    AmplitudeUse::Dload => "DLOAD",
                };
                let known: Vec<&str> = self
                    .deck
                    .amplitudes
                    .iter()
                    .map(|a| a.name.as_str())
                    .collect();
                return Err(self.invalid(
                    line,
                    kw,
                    format!(
                        "AMPLITUDE={name}: no *AMPLITUDE of that name (defined: {})",
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    ),
                ));
            };
            match what {
                AmplitudeUse::Boundary => self.deck.boundaries[k].amplitude = Some(a),
                AmplitudeUse::Cload => self.deck.cloads[k].amplitude = Some(a),
                AmplitudeUse::Dload => self.deck.dloads[k].amplitude = Some(a),
            }
        }
        Ok(())
    }

    /// Sections -> element materials: every element of a section's set
    /// gets the section's material (as the material is spelt) and
    /// orientation ([`Parser::assign_section`]). Solid sections first, then
    /// cohesive ones, each in input order.
    pub(super) fn assign_sections(&mut self) -> Result<(), InpError> {
        for i in 0..self.deck.solid_sections.len() {
            if self.deck.solid_sections[i].composite.is_some() {
                self.resolve_composite(i)?;
            }
        }
        #[allow(clippy::type_complexity)]
        let mut sections: Vec<(
            String,
            String,
            usize,
            bool,
            Option<String>,
            bool,
            Option<f64>,
        )> = self
            .deck
            .solid_sections
            .iter()
            .map(|s| {
                (
                    s.elset.clone(),
                    s.block_material(),
                    s.line,
                    false,
                    // a composite section's plies carry their axes
                    s.orientation.clone().filter(|_| s.composite.is_none()),
                    s.composite.is_some(),
                    s.thickness,
                )
            })
            .collect();
        sections.extend(self.deck.cohesive_sections.iter().map(|s| {
            (
                s.elset.clone(),
                s.material.clone(),
                s.line,
                true,
                None,
                false,
                s.out_of_plane,
            )
        }));
        for (elset, material, line, cohesive, orientation, composite, thickness) in sections {
            let orientation = match orientation {
                None => None,
                Some(o) => Some(self.section_orientation(line, o)?),
            };
            let kw = if cohesive {
                "COHESIVE SECTION"
            } else {
                "SOLID SECTION"
            };
            let set = match self.elset_index.get(&elset.to_uppercase()) {
                Some(&s) => s,
                None => return Err(self.unknown_set(line, kw, "element set", &elset)),
            };
            if composite {
                self.check_composite_elements(set, line)?;
                self.assign_section(set, &material, line, kw, &None)?;
                continue;
            }
            let m = self.section_material(line, kw, material)?;
            let mname = self.deck.materials[m].name.clone();
            if !cohesive && self.deck.materials[m].has_damage() {
                return Err(self.invalid(
                    line,
                    kw,
                    format!("material `{mname}` has damage options (a cohesive material): use it in a *COHESIVE SECTION for COH3D8 elements, not in a *SOLID SECTION"),
                ));
            }
            self.assign_section(set, &mname, line, kw, &orientation)?;
            for &e in &self.elsets[set].members {
                let plane = self.pre_blocks[self.elems[e].pre_block].shape.dimension() == 2;
                self.elems[e].thickness = thickness.filter(|_| plane);
            }
        }
        Ok(())
    }

    /// A composite section's names: its orientation, each ply's material
    /// (elastic, no damage) and orientation; an angle needs a rectangular
    /// section orientation (or none).
    fn resolve_composite(&mut self, i: usize) -> Result<(), InpError> {
        let kw = "SOLID SECTION";
        let s = self.deck.solid_sections[i].clone();
        let mut c = s.composite.clone().expect("a composite section");
        let index_of = |name: &str| {
            self.deck
                .orientations
                .iter()
                .position(|o| o.name == name)
                .expect("resolved")
        };
        c.orientation = match &s.orientation {
            None => None,
            Some(o) => Some(index_of(&self.section_orientation(s.line, o.clone())?)),
        };
        for ply in &mut c.plies {
            let m = self.section_material(ply.line, kw, ply.material.clone())?;
            let mat = &self.deck.materials[m];
            ply.material = mat.name.clone();
            if mat.has_damage() {
                return Err(self.invalid(
                    ply.line,
                    kw,
                    format!("ply material `{}` has damage options (a cohesive material): a ply needs an elastic material (*ELASTIC, TYPE=ISOTROPIC, ENGINEERING CONSTANTS, ORTHO or ANISO)", mat.name),
                ));
            }
            if matches!(mat.kind, InpMaterialKind::Traction(_)) {
                return Err(self.invalid(
                    ply.line,
                    kw,
                    format!("ply material `{}` is a cohesive (*ELASTIC, TYPE=TRACTION) material: a ply needs *ELASTIC, TYPE=ISOTROPIC, ENGINEERING CONSTANTS, ORTHO or ANISO", mat.name),
                ));
            }
            match &mut ply.axes {
                InpPlyAxes::Named { name, index } => {
                    *name = self.section_orientation(ply.line, name.clone())?;
                    *index = index_of(name);
                }
                InpPlyAxes::Angle(a) => {
                    if let Some(o) = c
                        .orientation
                        .filter(|&o| self.deck.orientations[o].cylindrical)
                    {
                        return Err(self.invalid(
                            ply.line,
                            kw,
                            format!("ply angle {a}: an angle is taken about axis 3 of the section's orientation, which must then be rectangular; `{}` is cylindrical: give the ply an *ORIENTATION name instead", self.deck.orientations[o].name),
                        ));
                    }
                }
                InpPlyAxes::Section => {}
            }
        }
        self.deck.solid_sections[i].composite = Some(c);
        Ok(())
    }

    /// A composite section holds the hexahedra C3D8, C3D20, C3D20R, C3D27.
    fn check_composite_elements(&self, set: usize, line: usize) -> Result<(), InpError> {
        for &e in &self.elsets[set].members {
            let el = &self.elems[e];
            let t = self.pre_blocks[el.pre_block].element_type;
            if !matches!(t, "h8" | "h20" | "h20r" | "h27") {
                let abaqus = match t {
                    "h8i" => "C3D8I",
                    "wedge6r" => "C3D6",
                    "wedge15" => "C3D15",
                    "inter8" => "COH3D8",
                    "inter6" => "COH3D6",
                    other => other,
                };
                return Err(self.invalid(
                    line,
                    "SOLID SECTION",
                    format!("COMPOSITE: element {} is a {abaqus} element; a composite section is integrated ply by ply in hexahedra C3D8, C3D20, C3D20R or C3D27 only (not C3D8I, whose incompatible modes are not layered, nor wedges)", el.label),
                ));
            }
        }
        Ok(())
    }

    /// The `*ORIENTATION` a solid section names (as the orientation is
    /// spelt).
    pub(super) fn section_orientation(&self, line: usize, o: String) -> Result<String, InpError> {
        let orientations = &self.deck.orientations;
        match orientations
            .iter()
            .find(|x| x.name.eq_ignore_ascii_case(&o))
        {
            Some(x) => Ok(x.name.clone()),
            None => {
                let valid: Vec<&str> = orientations.iter().map(|x| x.name.as_str()).collect();
                Err(InpError::UnknownName {
                    file: self.file.into(),
                    line,
                    keyword: "SOLID SECTION".into(),
                    kind: "orientation",
                    name: o,
                    valid: if valid.is_empty() {
                        "(none)".into()
                    } else {
                        valid.join(", ")
                    },
                })
            }
        }
    }

    /// Index of the material a section names.
    pub(super) fn section_material(
        &self,
        line: usize,
        kw: &str,
        material: String,
    ) -> Result<usize, InpError> {
        match self.material_index.get(&material.to_uppercase()) {
            Some(&m) => Ok(m),
            None => {
                let valid = if self.deck.materials.is_empty() {
                    "(none)".to_string()
                } else {
                    self.deck
                        .materials
                        .iter()
                        .map(|m| m.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                Err(InpError::UnknownName {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    kind: "material",
                    name: material,
                    valid,
                })
            }
        }
    }

    /// Give the elements of element set `set` the material `mname` and the
    /// orientation of the section of `line`: cohesive sections hold
    /// interface elements only, solid sections solids only, and an element
    /// keeps one material.
    pub(super) fn assign_section(
        &mut self,
        set: usize,
        mname: &str,
        line: usize,
        kw: &str,
        orientation: &Option<String>,
    ) -> Result<(), InpError> {
        let cohesive = kw == "COHESIVE SECTION";
        for &e in &self.elsets[set].members.clone() {
            let el = &self.elems[e];
            let shape = self.pre_blocks[el.pre_block].shape;
            if shape.is_interface() != cohesive {
                return Err(self.invalid(
                    line,
                    kw,
                    format!(
                        "element {} is a {} element; use {} for it",
                        el.label,
                        shape.name(),
                        if shape.is_interface() {
                            "*COHESIVE SECTION"
                        } else {
                            "*SOLID SECTION"
                        }
                    ),
                ));
            }
            match &el.material {
                Some((other, oline)) if *other != mname => {
                    return Err(self.invalid(
                        line,
                        kw,
                        format!(
                            "element {} already has material `{other}` from the section of line {oline}",
                            el.label
                        ),
                    ))
                }
                _ => {
                    self.elems[e].material = Some((mname.to_string(), line));
                    self.elems[e].orientation = orientation.clone();
                }
            }
        }
        Ok(())
    }

    /// The `** junta: curve` directive -> [`InpDeck::curve`]: its keys,
    /// node sets (as spelt) and components checked.
    pub(super) fn resolve_curve(&mut self) -> Result<(), InpError> {
        let Some((line, raw)) = self.curve_directive.take() else {
            return Ok(());
        };
        let kw = "** junta: curve";
        let get = |key: &str, required: bool| -> Result<Option<String>, InpError> {
            match raw.iter().find(|(k, _)| k == key) {
                Some((_, v)) => Ok(Some(v.clone())),
                None if required => Err(InpError::Invalid {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    message: format!("missing `{key}=`; the directive is `** junta: curve reaction_set=NSET reaction_component=x|y|z point_set=NSET point_component=x|y|z [relative_to=NSET]`"),
                }),
                None => Ok(None),
            }
        };
        let set_name = |name: String| -> Result<String, InpError> {
            match self.nset_index.get(&name.to_uppercase()) {
                Some(&i) => Ok(self.nsets[i].name.clone()),
                None => Err(self.unknown_set(line, kw, "node set", &name)),
            }
        };
        let component = |c: String| -> Result<String, InpError> {
            let l = c.to_ascii_lowercase();
            if matches!(l.as_str(), "x" | "y" | "z") {
                Ok(l)
            } else {
                Err(InpError::Invalid {
                    file: self.file.into(),
                    line,
                    keyword: kw.into(),
                    message: format!("component `{c}`: use x, y or z"),
                })
            }
        };
        let rs = get("reaction_set", true)?.unwrap_or_default();
        let rc = get("reaction_component", true)?.unwrap_or_default();
        let ps = get("point_set", true)?.unwrap_or_default();
        let pc = get("point_component", true)?.unwrap_or_default();
        let rel = get("relative_to", false)?;
        let curve = InpCurve {
            reaction_set: set_name(rs)?,
            reaction_component: component(rc)?,
            point_set: set_name(ps)?,
            point_component: component(pc)?,
            relative_to: rel.map(set_name).transpose()?,
            line,
        };
        self.deck.curve = Some(curve);
        Ok(())
    }

    /// The blocks: one per (pre-block, material, orientation), in input
    /// order, named after the pre-block or, when it splits,
    /// `<name>_<material>[_<orientation>]` (`nosection` for elements
    /// without a section, which are noted). Returns the element reference
    /// of each flat element id, the blocks and each block's orientation.
    pub(super) fn build_blocks(
        &mut self,
    ) -> (Vec<ElementRef>, Vec<ElementBlock>, Vec<Option<usize>>) {
        let mut refs = vec![
            ElementRef {
                block: 0,
                element: 0
            };
            self.elems.len()
        ];
        let mut blocks: Vec<ElementBlock> = Vec::new();
        let mut block_orientations = Vec::new();
        for (pb_i, pb) in self.pre_blocks.iter().enumerate() {
            // one block per (material, orientation, plane thickness)
            let mut mats: Vec<(String, Option<String>, Option<f64>)> = Vec::new();
            for e in self.elems.iter().filter(|e| e.pre_block == pb_i) {
                let m = e.material.as_ref().map(|m| m.0.clone()).unwrap_or_default();
                let key = (m, e.orientation.clone(), e.thickness);
                if !mats.contains(&key) {
                    mats.push(key);
                }
            }
            let thicknesses = mats
                .iter()
                .filter_map(|k| k.2.map(f64::to_bits))
                .collect::<std::collections::HashSet<_>>()
                .len();
            let split = mats.len() > 1;
            for (m, o, t) in &mats {
                let bi = blocks.len();
                let name = if split {
                    let mut n =
                        format!("{}_{}", pb.name, if m.is_empty() { "nosection" } else { m });
                    if let Some(o) = o {
                        n = format!("{n}_{o}");
                    }
                    if let (Some(t), true) = (t, thicknesses > 1) {
                        n = format!("{n}_t{t}");
                    }
                    n
                } else {
                    pb.name.clone()
                };
                block_orientations.push(
                    o.as_ref()
                        .and_then(|o| self.deck.orientations.iter().position(|x| &x.name == o)),
                );
                self.deck.block_thickness.push(*t);
                let mut b = ElementBlock {
                    name,
                    shape: pb.shape,
                    connectivity: Vec::new(),
                    element_type: pb.element_type.into(),
                    material: m.clone(),
                };
                for (id, e) in self.elems.iter().enumerate() {
                    let em = e.material.as_ref().map(|x| x.0.as_str()).unwrap_or("");
                    if e.pre_block == pb_i && em == m && &e.orientation == o && e.thickness == *t {
                        refs[id] = ElementRef {
                            block: bi,
                            element: b.len(),
                        };
                        b.connectivity.extend_from_slice(&e.conn);
                    }
                }
                blocks.push(b);
            }
            let unassigned = self
                .elems
                .iter()
                .filter(|e| e.pre_block == pb_i && e.material.is_none())
                .count();
            if unassigned > 0 {
                self.deck.notes.push(format!(
                    "{unassigned} element(s) of block `{}` have no section (material left empty)",
                    pb.name
                ));
            }
        }
        (refs, blocks, block_orientations)
    }

    /// The mesh of `blocks` with the node and element sets, the element
    /// labels and the distributed loads' elements (`refs`: the reference
    /// of each flat element id), validated; the deck that holds it.
    pub(super) fn into_deck(
        mut self,
        refs: Vec<ElementRef>,
        blocks: Vec<ElementBlock>,
        block_orientations: Vec<Option<usize>>,
        dload_ids: Vec<Vec<(usize, usize)>>,
    ) -> Result<InpDeck, InpError> {
        let mut mesh = Mesh {
            nodes: self.nodes,
            node_labels: self.labels,
            blocks,
            ..Mesh::default()
        };
        for s in self.nsets {
            let mut v = s.members;
            v.sort_unstable();
            v.dedup();
            mesh.node_sets.insert(s.name, v);
        }
        for s in self.elsets {
            let mut v: Vec<ElementRef> = s.members.iter().map(|&e| refs[e]).collect();
            v.sort_unstable();
            v.dedup();
            mesh.element_sets.insert(s.name, v);
        }
        mesh.element_labels = mesh.blocks.iter().map(|b| vec![0; b.len()]).collect();
        for (id, e) in self.elems.iter().enumerate() {
            self.deck.element_labels.insert(e.label, refs[id]);
            mesh.element_labels[refs[id].block][refs[id].element] = e.label;
        }
        for (d, ids) in self.deck.dloads.iter_mut().zip(dload_ids) {
            d.elements = ids.into_iter().map(|(e, face)| (refs[e], face)).collect();
        }
        mesh.validate().map_err(|e| InpError::Invalid {
            file: self.file.into(),
            line: 0,
            keyword: "(mesh)".into(),
            message: e.to_string(),
        })?;
        self.deck.mesh = mesh;
        self.deck.block_orientations = block_orientations;
        Ok(self.deck)
    }
}
