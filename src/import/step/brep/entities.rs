//! Typed access to the entity instances of an exchange structure: look-ups by id that check the
//! entity type, and parameter readers whose errors name the instance (`#id` and line).

use std::collections::{BTreeMap, BTreeSet};

use super::{BrepError, ErrorKind};
use crate::import::step::part21::{Exchange, Instance, Param, Record};

/// Deepest parameter nesting followed when indexing references (aggregates deeper than this are
/// not geometry Talas reads).
const MAX_PARAM_DEPTH: usize = 16;

/// The exchange structure plus a reverse index: which instances refer to which.
pub(super) struct Model<'a> {
    /// The parsed file.
    pub ex: &'a Exchange,
    /// Referenced id → ids of the instances that refer to it (sorted, no duplicates).
    users: BTreeMap<u64, Vec<u64>>,
}

impl<'a> Model<'a> {
    /// Index the references of every instance.
    pub fn new(ex: &'a Exchange) -> Self {
        let mut users: BTreeMap<u64, BTreeSet<u64>> = BTreeMap::new();
        for inst in ex.instances.values() {
            let mut refs = Vec::new();
            for rec in &inst.records {
                collect_refs(&rec.params, 0, &mut refs);
            }
            for r in refs {
                users.entry(r).or_default().insert(inst.id);
            }
        }
        let users = users
            .into_iter()
            .map(|(k, v)| (k, v.into_iter().collect()))
            .collect();
        Self { ex, users }
    }

    /// The instance `#id`, if the file has it.
    pub fn get(&self, id: u64) -> Option<Entity<'a>> {
        self.ex.instances.get(&id).map(|inst| Entity { inst })
    }

    /// The instance `#id` referred to by `from`; a dangling reference is an error naming `from`.
    pub fn entity(&self, from: Entity<'_>, id: u64) -> Result<Entity<'a>, BrepError> {
        self.get(id).ok_or_else(|| {
            from.error(
                ErrorKind::Dangling,
                format!("refers to #{id}, which is not in the file"),
            )
        })
    }

    /// The `name` record of the instance `#id` referred to by `from`; a wrong type is an error
    /// naming both instances.
    pub fn typed(&self, from: Entity<'_>, id: u64, name: &str) -> Result<Args<'a>, BrepError> {
        self.entity(from, id)?.args(name).map_err(|mut err| {
            err.message
                .push_str(&format!(" (referred to by #{})", from.id()));
            err
        })
    }

    /// Ids of the instances that refer to `#id`.
    pub fn users(&self, id: u64) -> &[u64] {
        self.users.get(&id).map_or(&[], Vec::as_slice)
    }

    /// Every instance having a record named `name`, in id order.
    pub fn all_of<'s>(&'s self, name: &'s str) -> impl Iterator<Item = Entity<'a>> + 's {
        self.ex
            .instances
            .values()
            .map(|inst| Entity { inst })
            .filter(move |e| e.has(name))
    }
}

fn collect_refs(params: &[Param], depth: usize, out: &mut Vec<u64>) {
    if depth > MAX_PARAM_DEPTH {
        return;
    }
    for p in params {
        match p {
            Param::Ref(r) => out.push(*r),
            Param::List(items) => collect_refs(items, depth + 1, out),
            Param::Typed(_, inner) => {
                collect_refs(std::slice::from_ref(inner.as_ref()), depth + 1, out)
            }
            _ => {}
        }
    }
}

/// One entity instance.
#[derive(Clone, Copy, Debug)]
pub(super) struct Entity<'a> {
    /// The instance.
    pub inst: &'a Instance,
}

impl<'a> Entity<'a> {
    /// Instance id.
    pub fn id(self) -> u64 {
        self.inst.id
    }

    /// Does the instance have a record named `name`?
    pub fn has(self, name: &str) -> bool {
        self.inst.records.iter().any(|r| r.name == name)
    }

    /// The record named `name`, if any.
    pub fn record(self, name: &str) -> Option<&'a Record> {
        self.inst.records.iter().find(|r| r.name == name)
    }

    /// Type name for messages: the record name, or `(A B C)` for a complex instance.
    pub fn type_name(self) -> String {
        if self.inst.complex || self.inst.records.len() != 1 {
            let names: Vec<&str> = self.inst.records.iter().map(|r| r.name.as_str()).collect();
            format!("({})", names.join(" "))
        } else {
            self.inst
                .records
                .first()
                .map(|r| r.name.clone())
                .unwrap_or_default()
        }
    }

    /// An error about this instance.
    pub fn error(self, kind: ErrorKind, message: impl Into<String>) -> BrepError {
        BrepError {
            id: Some(self.inst.id),
            line: Some(self.inst.line),
            kind,
            message: message.into(),
        }
    }

    /// The parameters of the record named `name`; a wrong entity type is an error.
    pub fn args(self, name: &str) -> Result<Args<'a>, BrepError> {
        self.record(name)
            .map(|rec| Args { ent: self, rec })
            .ok_or_else(|| {
                self.error(
                    ErrorKind::WrongType,
                    format!("expected {name}, found {}", self.type_name()),
                )
            })
    }

    /// The parameters of the first record whose name is one of `names`.
    pub fn args_any(self, names: &[&str]) -> Result<Args<'a>, BrepError> {
        self.inst
            .records
            .iter()
            .find(|r| names.contains(&r.name.as_str()))
            .map(|rec| Args { ent: self, rec })
            .ok_or_else(|| {
                self.error(
                    ErrorKind::WrongType,
                    format!(
                        "expected one of {}, found {}",
                        names.join(", "),
                        self.type_name()
                    ),
                )
            })
    }
}

/// The parameters of one record of an entity, read with errors that name the entity.
#[derive(Clone, Copy, Debug)]
pub(super) struct Args<'a> {
    /// The entity.
    pub ent: Entity<'a>,
    /// The record read.
    pub rec: &'a Record,
}

impl<'a> Args<'a> {
    fn bad(self, i: usize, what: &str, expected: &str) -> BrepError {
        self.ent.error(
            ErrorKind::BadParameter,
            format!(
                "{} parameter {} ({what}): expected {expected}",
                self.rec.name,
                i + 1
            ),
        )
    }

    /// Parameter `i`, unwrapping typed values such as `LENGTH_MEASURE(1.)`.
    pub fn param(self, i: usize, what: &str) -> Result<&'a Param, BrepError> {
        let p = self.rec.params.get(i).ok_or_else(|| {
            self.ent.error(
                ErrorKind::BadParameter,
                format!(
                    "{} has {} parameters; parameter {} ({what}) is missing",
                    self.rec.name,
                    self.rec.params.len(),
                    i + 1
                ),
            )
        })?;
        Ok(untyped(p))
    }

    /// Is parameter `i` absent, `$` or `*`?
    pub fn is_unset(self, i: usize) -> bool {
        matches!(
            self.rec.params.get(i).map(untyped),
            None | Some(Param::Unset | Param::Derived)
        )
    }

    /// A finite real (an integer is accepted).
    pub fn real(self, i: usize, what: &str) -> Result<f64, BrepError> {
        param_real(self.param(i, what)?).ok_or_else(|| self.bad(i, what, "a finite number"))
    }

    /// An integer.
    pub fn int(self, i: usize, what: &str) -> Result<i64, BrepError> {
        match self.param(i, what)? {
            Param::Integer(n) => Ok(*n),
            _ => Err(self.bad(i, what, "an integer")),
        }
    }

    /// A boolean or logical `.T.`/`.F.` (`.U.` reads as true, as Open CASCADE does).
    pub fn boolean(self, i: usize, what: &str) -> Result<bool, BrepError> {
        match self.param(i, what)? {
            Param::Enum(e) if e == "T" || e == "U" => Ok(true),
            Param::Enum(e) if e == "F" => Ok(false),
            _ => Err(self.bad(i, what, ".T. or .F.")),
        }
    }

    /// A string.
    pub fn string(self, i: usize, what: &str) -> Result<&'a str, BrepError> {
        match self.param(i, what)? {
            Param::String(s) => Ok(s.as_str()),
            _ => Err(self.bad(i, what, "a string")),
        }
    }

    /// A reference `#id`.
    pub fn reference(self, i: usize, what: &str) -> Result<u64, BrepError> {
        match self.param(i, what)? {
            Param::Ref(r) => Ok(*r),
            _ => Err(self.bad(i, what, "a reference")),
        }
    }

    /// An aggregate.
    pub fn list(self, i: usize, what: &str) -> Result<&'a [Param], BrepError> {
        match self.param(i, what)? {
            Param::List(items) => Ok(items.as_slice()),
            _ => Err(self.bad(i, what, "a list")),
        }
    }

    /// An aggregate of references.
    pub fn refs(self, i: usize, what: &str) -> Result<Vec<u64>, BrepError> {
        self.list(i, what)?
            .iter()
            .map(|p| match untyped(p) {
                Param::Ref(r) => Ok(*r),
                _ => Err(self.bad(i, what, "a list of references")),
            })
            .collect()
    }

    /// An aggregate of finite reals.
    pub fn reals(self, i: usize, what: &str) -> Result<Vec<f64>, BrepError> {
        self.list(i, what)?
            .iter()
            .map(|p| param_real(p).ok_or_else(|| self.bad(i, what, "a list of finite numbers")))
            .collect()
    }

    /// An aggregate of integers.
    pub fn ints(self, i: usize, what: &str) -> Result<Vec<i64>, BrepError> {
        self.list(i, what)?
            .iter()
            .map(|p| match untyped(p) {
                Param::Integer(n) => Ok(*n),
                _ => Err(self.bad(i, what, "a list of integers")),
            })
            .collect()
    }

    /// A list of lists of references (B-spline surface control points).
    pub fn ref_grid(self, i: usize, what: &str) -> Result<Vec<Vec<u64>>, BrepError> {
        self.list(i, what)?
            .iter()
            .map(|row| match untyped(row) {
                Param::List(items) => items
                    .iter()
                    .map(|p| match untyped(p) {
                        Param::Ref(r) => Ok(*r),
                        _ => Err(self.bad(i, what, "a list of lists of references")),
                    })
                    .collect(),
                _ => Err(self.bad(i, what, "a list of lists")),
            })
            .collect()
    }

    /// A list of lists of finite reals (B-spline surface weights).
    pub fn real_grid(self, i: usize, what: &str) -> Result<Vec<Vec<f64>>, BrepError> {
        self.list(i, what)?
            .iter()
            .map(|row| match untyped(row) {
                Param::List(items) => items
                    .iter()
                    .map(|p| param_real(p).ok_or_else(|| self.bad(i, what, "finite numbers")))
                    .collect(),
                _ => Err(self.bad(i, what, "a list of lists")),
            })
            .collect()
    }
}

/// A parameter with any type wrapper `NAME(value)` removed.
pub(super) fn untyped(p: &Param) -> &Param {
    let mut p = p;
    let mut depth = 0;
    while let Param::Typed(_, inner) = p {
        p = inner.as_ref();
        depth += 1;
        if depth > MAX_PARAM_DEPTH {
            break;
        }
    }
    p
}

/// A finite real from a real or integer parameter.
#[allow(clippy::cast_precision_loss)]
pub(super) fn param_real(p: &Param) -> Option<f64> {
    match untyped(p) {
        Param::Real(x) if x.is_finite() => Some(*x),
        Param::Integer(n) => Some(*n as f64),
        _ => None,
    }
}
