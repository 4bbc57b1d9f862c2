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
use super::representation::representation_record;
use super::topology::Builder;
use super::units::Units;
use crate::diagnostics::Diagnostic;

/// Deepest product or representation nesting followed.
pub(super) const MAX_DEPTH: usize = 32;

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
    pub(super) units: BTreeMap<u64, Units>,
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
    pub(super) fn within_budget(&mut self) -> bool {
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

    pub(super) fn model(&self) -> &'m Model<'a> {
        self.b.model
    }

    pub(super) fn warn(&mut self, e: Option<Entity<'_>>, message: impl Into<String>) {
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

    /// Files without product structure: every shape representation that no mapped item and no
    /// placing relationship uses (those are reached, placed, from their parents).
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
                    .any(|u| model.get(*u).is_some_and(|u| places(u, e.id())))
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
}

/// Does `user` place representation `#rep` inside another: a `REPRESENTATION_MAP` of it, or a
/// relationship with a transformation whose `rep_1` (the placed one) it is?
fn places(user: Entity<'_>, rep: u64) -> bool {
    user.has("REPRESENTATION_MAP")
        || (user.has("REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION")
            && user
                .args("REPRESENTATION_RELATIONSHIP")
                .and_then(|a| a.reference(2, "rep_1"))
                .ok()
                == Some(rep))
}

/// Instances referring to `id` that have a record named `name`.
pub(super) fn users_with<'m, 'a>(
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
