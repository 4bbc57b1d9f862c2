//! What to transfer, as Open CASCADE does: the root product definitions (those no
//! `NEXT_ASSEMBLY_USAGE_OCCURRENCE` uses as a component), their shape representations (through
//! `SHAPE_DEFINITION_REPRESENTATION` and plain `SHAPE_REPRESENTATION_RELATIONSHIP`s), their
//! components placed by `CONTEXT_DEPENDENT_SHAPE_REPRESENTATION`s, and `MAPPED_ITEM`s. Every
//! instance of a component becomes its own faces with the placement applied. Cycles and
//! self references are cut with a warning.

use std::collections::{BTreeMap, BTreeSet};

use super::BrepError;
use super::entities::{Entity, Model};
use super::placement::Rigid;
use super::points::Geo;
use super::topology::{Builder, Placed};
use super::units::{Units, context_units};
use crate::diagnostics::Diagnostic;
use crate::geometry::frame::Frame;

/// Deepest product or representation nesting followed.
const MAX_DEPTH: usize = 32;

/// Most product and representation instances transferred: a shared component used twice at
/// every level of a deep assembly would otherwise multiply without end.
const MAX_INSTANCES: usize = 100_000;

/// Most faces built before the transfer stops.
const MAX_FACES: usize = 5_000_000;

/// Record names of product definitions.
const PRODUCT_DEFINITIONS: [&str; 2] = [
    "PRODUCT_DEFINITION",
    "PRODUCT_DEFINITION_WITH_ASSOCIATED_DOCUMENTS",
];

/// Walks the product structure and representations, filling a [`Builder`].
pub(super) struct Transfer<'m, 'a> {
    /// The part being built.
    pub b: Builder<'m, 'a>,
    units: BTreeMap<u64, Units>,
    /// Product and representation instances transferred so far.
    instances: usize,
    /// Set once the instance or face budget is spent (warned once).
    truncated: bool,
}

impl<'m, 'a> Transfer<'m, 'a> {
    /// Start on `model`.
    pub fn new(model: &'m Model<'a>) -> Self {
        Self {
            b: Builder::new(model),
            units: BTreeMap::new(),
            instances: 0,
            truncated: false,
        }
    }

    /// Count one more instance; false (with one warning) once the budget is spent.
    fn within_budget(&mut self) -> bool {
        self.instances += 1;
        if self.instances > MAX_INSTANCES || self.b.part.faces.len() > MAX_FACES {
            if !self.truncated {
                self.truncated = true;
                self.warn(
                    None,
                    format!(
                        "model too large: transfer stopped after {} instances and {} faces",
                        self.instances - 1,
                        self.b.part.faces.len()
                    ),
                );
            }
            return false;
        }
        true
    }

    fn model(&self) -> &'m Model<'a> {
        self.b.model
    }

    fn warn(&mut self, e: Option<Entity<'_>>, message: impl Into<String>) {
        self.b.part.diagnostics.push(Diagnostic::warning(
            e.map(|e| format!("#{}", e.id())),
            message,
        ));
    }

    /// Transfer everything the roots reach.
    pub fn run(&mut self) {
        let model = self.model();
        let pds: Vec<Entity<'a>> = model
            .ex
            .instances
            .values()
            .map(|inst| Entity { inst })
            .filter(|e| PRODUCT_DEFINITIONS.iter().any(|n| e.has(n)))
            .collect();
        if pds.is_empty() {
            self.run_without_products();
            return;
        }
        let components: BTreeSet<u64> = model
            .all_of("NEXT_ASSEMBLY_USAGE_OCCURRENCE")
            .filter_map(|n| {
                n.args("NEXT_ASSEMBLY_USAGE_OCCURRENCE")
                    .ok()?
                    .reference(4, "related")
                    .ok()
            })
            .collect();
        for pd in pds.into_iter().filter(|pd| !components.contains(&pd.id())) {
            if self.b.part.name.is_empty() {
                self.b.part.name = product_name(model, pd).unwrap_or_default();
            }
            self.product(pd, Rigid::IDENTITY, &mut Vec::new());
        }
    }

    /// Files without product structure: every shape representation no mapped item uses.
    fn run_without_products(&mut self) {
        let model = self.model();
        let mut done = BTreeSet::new();
        let reps: Vec<Entity<'a>> = model
            .ex
            .instances
            .values()
            .map(|inst| Entity { inst })
            .filter(|e| representation_record(*e).is_some())
            .filter(|e| {
                !model
                    .users(e.id())
                    .iter()
                    .any(|u| model.get(*u).is_some_and(|u| u.has("REPRESENTATION_MAP")))
            })
            .collect();
        for rep in reps {
            self.representation(rep, Rigid::IDENTITY, &mut done, &mut Vec::new());
        }
    }

    /// Transfer a product definition and its components.
    fn product(&mut self, pd: Entity<'a>, xf: Rigid, stack: &mut Vec<u64>) {
        if !self.within_budget() {
            return;
        }
        if stack.contains(&pd.id()) {
            self.warn(
                Some(pd),
                "assembly cycle: product used inside itself; not followed again",
            );
            return;
        }
        if stack.len() >= MAX_DEPTH {
            self.warn(Some(pd), "assembly nests too deeply; not followed");
            return;
        }
        stack.push(pd.id());
        let model = self.model();
        let mut done = BTreeSet::new();
        for rep in shape_reps(model, pd) {
            self.representation(rep, xf, &mut done, &mut Vec::new());
        }
        let usages: Vec<Entity<'a>> = users_with(model, pd.id(), "NEXT_ASSEMBLY_USAGE_OCCURRENCE")
            .filter(|n| {
                n.args("NEXT_ASSEMBLY_USAGE_OCCURRENCE")
                    .and_then(|a| a.reference(3, "relating"))
                    .ok()
                    == Some(pd.id())
            })
            .collect();
        for nauo in usages {
            let child = match nauo
                .args("NEXT_ASSEMBLY_USAGE_OCCURRENCE")
                .and_then(|a| a.reference(4, "related"))
                .and_then(|id| model.entity(nauo, id))
            {
                Ok(c) => c,
                Err(err) => {
                    self.warn(Some(nauo), format!("component skipped: {err}"));
                    continue;
                }
            };
            let placement = match self.component_placement(nauo, child) {
                Ok(t) => t,
                Err(err) => {
                    self.warn(Some(nauo), format!("component placement ignored: {err}"));
                    Rigid::IDENTITY
                }
            };
            self.product(child, xf.then_after(&placement), stack);
        }
        stack.pop();
    }

    /// Placement of the component of `nauo` in its parent (identity when none is given).
    fn component_placement(
        &mut self,
        nauo: Entity<'a>,
        child: Entity<'a>,
    ) -> Result<Rigid, BrepError> {
        let model = self.model();
        let child_reps: BTreeSet<u64> = shape_reps(model, child).map(|e| e.id()).collect();
        let cdsr = users_with(model, nauo.id(), "PRODUCT_DEFINITION_SHAPE")
            .flat_map(|pds| users_with(model, pds.id(), "CONTEXT_DEPENDENT_SHAPE_REPRESENTATION"))
            .next();
        let Some(cdsr) = cdsr else {
            return Ok(Rigid::IDENTITY);
        };
        let rel = model.entity(
            cdsr,
            cdsr.args("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION")?
                .reference(0, "representation_relation")?,
        )?;
        let (rep_1, rep_2, t) = self.relationship(rel)?;
        let t = t.unwrap_or(Rigid::IDENTITY);
        // rep_1 is normally the component's; a writer that swapped them gets the inverse.
        Ok(
            if !child_reps.contains(&rep_1) && child_reps.contains(&rep_2) {
                t.inverse()
            } else {
                t
            },
        )
    }

    /// A representation relationship: `(rep_1, rep_2, motion placing rep_1 in rep_2)`.
    fn relationship(&mut self, rel: Entity<'a>) -> Result<(u64, u64, Option<Rigid>), BrepError> {
        let model = self.model();
        let a = rel.args_any(&[
            "REPRESENTATION_RELATIONSHIP",
            "SHAPE_REPRESENTATION_RELATIONSHIP",
        ])?;
        let (rep_1, rep_2) = (a.reference(2, "rep_1")?, a.reference(3, "rep_2")?);
        if !rel.has("REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION") {
            return Ok((rep_1, rep_2, None));
        }
        let op = model.entity(
            rel,
            rel.args("REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION")?
                .reference(0, "transformation_operator")?,
        )?;
        let idt = op.args("ITEM_DEFINED_TRANSFORMATION")?;
        let from = self.frame_in(op, idt.reference(2, "transform_item_1")?, rep_1)?;
        let to = self.frame_in(op, idt.reference(3, "transform_item_2")?, rep_2)?;
        Ok((rep_1, rep_2, Some(Rigid::between(&from, &to))))
    }

    /// The placement `#id` read in the units of representation `#rep`.
    fn frame_in(&mut self, from: Entity<'a>, id: u64, rep: u64) -> Result<Frame, BrepError> {
        let model = self.model();
        let units = match model.get(rep) {
            Some(r) => self.rep_units(r),
            None => Units::MM_RAD,
        };
        Geo { model, units }.placement(from, id)
    }

    /// Units of a representation's context (cached; mm with a warning when none is declared).
    fn rep_units(&mut self, rep: Entity<'a>) -> Units {
        let model = self.model();
        let ctx = representation_record(rep).and_then(|a| a.reference(2, "context_of_items").ok());
        let Some(ctx_id) = ctx else {
            self.warn(
                Some(rep),
                "representation has no context; lengths read as mm",
            );
            return Units::MM_RAD;
        };
        if let Some(u) = self.units.get(&ctx_id) {
            return *u;
        }
        let units = match model
            .entity(rep, ctx_id)
            .and_then(|ctx| context_units(model, ctx))
        {
            Ok(cu) => {
                if cu.missing_length {
                    self.b.part.diagnostics.push(Diagnostic::warning(
                        Some(format!("#{ctx_id}")),
                        "no length unit declared; lengths read as mm",
                    ));
                }
                cu.units
            }
            Err(err) => {
                self.b.part.diagnostics.push(Diagnostic::warning(
                    Some(format!("#{ctx_id}")),
                    format!("units unreadable ({err}); lengths read as mm"),
                ));
                Units::MM_RAD
            }
        };
        self.units.insert(ctx_id, units);
        units
    }

    /// Transfer a shape representation's items and the representations related to it.
    fn representation(
        &mut self,
        rep: Entity<'a>,
        xf: Rigid,
        done: &mut BTreeSet<u64>,
        path: &mut Vec<u64>,
    ) {
        if done.contains(&rep.id()) {
            return;
        }
        if path.contains(&rep.id()) {
            self.warn(
                Some(rep),
                "representation used inside itself; not followed again",
            );
            return;
        }
        if path.len() >= MAX_DEPTH {
            self.warn(Some(rep), "representations nest too deeply; not followed");
            return;
        }
        if !done.insert(rep.id()) || !self.within_budget() {
            return;
        }
        let Some(args) = representation_record(rep) else {
            self.warn(
                Some(rep),
                format!("expected a shape representation, found {}", rep.type_name()),
            );
            return;
        };
        let items = match args.refs(1, "items") {
            Ok(items) => items,
            Err(err) => {
                self.warn(Some(rep), format!("representation skipped: {err}"));
                return;
            }
        };
        path.push(rep.id());
        let model = self.model();
        let units = self.rep_units(rep);
        let mut placed = Placed::new(Geo { model, units }, xf);
        for item in items {
            if let Err(err) = self.item(&mut placed, rep, item, done, path) {
                self.warn(Some(rep), format!("item #{item} skipped: {err}"));
            }
        }
        // Plain relationships (not component placements) bring in further representations.
        let relations: Vec<Entity<'a>> = model
            .users(rep.id())
            .iter()
            .filter_map(|u| model.get(*u))
            .filter(|u| {
                u.has("SHAPE_REPRESENTATION_RELATIONSHIP") || u.has("REPRESENTATION_RELATIONSHIP")
            })
            .filter(|u| {
                users_with(model, u.id(), "CONTEXT_DEPENDENT_SHAPE_REPRESENTATION")
                    .next()
                    .is_none()
            })
            .collect();
        for rel in relations {
            let (rep_1, rep_2, t) = match self.relationship(rel) {
                Ok(r) => r,
                Err(err) => {
                    self.warn(Some(rel), format!("relationship skipped: {err}"));
                    continue;
                }
            };
            let (other, motion) = if rep_1 == rep.id() {
                (rep_2, t.map(|t| t.inverse()))
            } else {
                (rep_1, t)
            };
            let Some(other) = model.get(other) else {
                continue;
            };
            let sub_xf = motion.map_or(xf, |m| xf.then_after(&m));
            self.representation(other, sub_xf, done, path);
        }
        path.pop();
    }

    /// One representation item: a solid, shell, surface model, face or mapped item.
    fn item(
        &mut self,
        pl: &mut Placed<'m, 'a>,
        rep: Entity<'a>,
        id: u64,
        done: &mut BTreeSet<u64>,
        path: &mut Vec<u64>,
    ) -> Result<(), BrepError> {
        let model = self.model();
        let e = model.entity(rep, id)?;
        if let Ok(a) = e.args_any(&["MANIFOLD_SOLID_BREP", "FACETED_BREP", "BREP_WITH_VOIDS"]) {
            self.b.shell(pl, e, a.reference(1, "outer")?, false, 0)?;
            if e.has("BREP_WITH_VOIDS") {
                for void in e.args("BREP_WITH_VOIDS")?.refs(2, "voids")? {
                    self.b.shell(pl, e, void, false, 0)?;
                }
            }
        } else if let Ok(a) = e.args_any(&["SHELL_BASED_SURFACE_MODEL", "FACE_BASED_SURFACE_MODEL"])
        {
            for shell in a.refs(1, "boundary")? {
                if let Err(err) = self.b.shell(pl, e, shell, false, 0) {
                    self.warn(Some(e), format!("shell #{shell} skipped: {err}"));
                }
            }
        } else if e.has("CLOSED_SHELL") || e.has("OPEN_SHELL") {
            self.b.shell(pl, rep, id, false, 0)?;
        } else if e.has("ADVANCED_FACE") || e.has("FACE_SURFACE") {
            self.b.lone_face(pl, rep, id);
        } else if e.has("MAPPED_ITEM") {
            let a = e.args("MAPPED_ITEM")?;
            let map = model.entity(e, a.reference(1, "mapping_source")?)?;
            let m = map.args("REPRESENTATION_MAP")?;
            let mapped = model.entity(map, m.reference(1, "mapped_representation")?)?;
            let origin = self.frame_in(map, m.reference(0, "mapping_origin")?, mapped.id())?;
            let target = self.frame_in(e, a.reference(2, "mapping_target")?, rep.id())?;
            let xf = pl.xf.then_after(&Rigid::between(&origin, &target));
            // A mapped representation is a separate instance: transfer it even if seen before.
            let mut fresh = BTreeSet::new();
            self.representation(mapped, xf, &mut fresh, path);
            done.extend(fresh);
        } else if let Ok(a) = e.args_any(&["GEOMETRIC_SET", "GEOMETRIC_CURVE_SET"]) {
            // As Open CASCADE: a bounded surface in a geometric set becomes an untrimmed face;
            // points and curves carry no faces.
            for element in a.refs(1, "elements")? {
                self.b.set_surface(pl, e, element);
            }
        }
        // Other items (placements, styled items, ...) carry no faces.
        Ok(())
    }
}

/// The record of a representation (`*REPRESENTATION(name, items, context)`), if `e` is one.
fn representation_record(e: Entity<'_>) -> Option<super::entities::Args<'_>> {
    e.inst
        .records
        .iter()
        .find(|r| {
            r.name.ends_with("REPRESENTATION")
                && r.params.len() >= 3
                && r.name != "DEFINITIONAL_REPRESENTATION"
        })
        .map(|rec| super::entities::Args { ent: e, rec })
        .filter(|a| a.rec.name.contains("SHAPE_REPRESENTATION") || a.rec.name == "REPRESENTATION")
}

/// Instances referring to `id` that have a record named `name`.
fn users_with<'m, 'a>(
    model: &'m Model<'a>,
    id: u64,
    name: &'static str,
) -> impl Iterator<Item = Entity<'a>> + 'm {
    model
        .users(id)
        .iter()
        .filter_map(|u| model.get(*u))
        .filter(move |u| u.has(name))
}

/// Shape representations of a product definition: PD ← PRODUCT_DEFINITION_SHAPE ←
/// SHAPE_DEFINITION_REPRESENTATION → representation. Tolerant of writers that put an extra
/// parameter before the reference (the reverse index already says who refers to whom).
fn shape_reps<'m, 'a>(
    model: &'m Model<'a>,
    pd: Entity<'a>,
) -> impl Iterator<Item = Entity<'a>> + 'm {
    users_with(model, pd.id(), "PRODUCT_DEFINITION_SHAPE").flat_map(move |pds| {
        users_with(model, pds.id(), "SHAPE_DEFINITION_REPRESENTATION").filter_map(move |sdr| {
            let a = sdr.args("SHAPE_DEFINITION_REPRESENTATION").ok()?;
            let rep = a.reference(1, "used_representation").ok()?;
            (rep != pds.id()).then(|| model.get(rep)).flatten()
        })
    })
}

/// The name of the product a product definition defines (PD → formation → PRODUCT; the first
/// reference of each, for writers that add parameters).
fn product_name(model: &Model<'_>, pd: Entity<'_>) -> Option<String> {
    let first_ref = |e: Entity<'_>| {
        e.inst.records.first()?.params.iter().find_map(|p| match p {
            crate::import::step::part21::Param::Ref(r) => Some(*r),
            _ => None,
        })
    };
    let formation = model.get(first_ref(pd)?)?;
    let product = model.get(first_ref(formation)?)?;
    let pa = product.args("PRODUCT").ok()?;
    let name = pa
        .string(1, "name")
        .ok()
        .filter(|s| !s.trim().is_empty())
        .or_else(|| pa.string(0, "id").ok())?;
    Some(name.to_string())
}
