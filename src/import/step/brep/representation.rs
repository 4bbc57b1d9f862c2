//! Shape representations: their units, their items (solids, shells, surface models, faces,
//! mapped items, geometric sets) and the representations related to them by
//! `SHAPE_REPRESENTATION_RELATIONSHIP`s, with the placements those carry.

use std::collections::BTreeSet;

use super::BrepError;
use super::assembly::{MAX_DEPTH, Transfer, users_with};
use super::entities::{Args, Entity};
use super::placement::Rigid;
use super::points::Geo;
use super::topology::Placed;
use super::units::{Units, context_units};
use crate::diagnostics::Diagnostic;
use crate::geometry::frame::Frame;

impl<'m, 'a> Transfer<'m, 'a> {
    /// A representation relationship: `(rep_1, rep_2, motion placing rep_1 in rep_2)`.
    pub(super) fn relationship(
        &mut self,
        rel: Entity<'a>,
    ) -> Result<(u64, u64, Option<Rigid>), BrepError> {
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
    pub(super) fn frame_in(
        &mut self,
        from: Entity<'a>,
        id: u64,
        rep: u64,
    ) -> Result<Frame, BrepError> {
        let model = self.model();
        let units = match model.get(rep) {
            Some(r) => self.rep_units(r),
            None => Units::MM_RAD,
        };
        Geo { model, units }.placement(from, id)
    }

    /// Units of a representation's context (cached; mm with a warning when none is declared).
    pub(super) fn rep_units(&mut self, rep: Entity<'a>) -> Units {
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
    pub(super) fn representation(
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
pub(super) fn representation_record(e: Entity<'_>) -> Option<Args<'_>> {
    e.inst
        .records
        .iter()
        .find(|r| {
            r.name.ends_with("REPRESENTATION")
                && r.params.len() >= 3
                && r.name != "DEFINITIONAL_REPRESENTATION"
        })
        .map(|rec| Args { ent: e, rec })
        .filter(|a| a.rec.name.contains("SHAPE_REPRESENTATION") || a.rec.name == "REPRESENTATION")
}
