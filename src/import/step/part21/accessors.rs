//! Convenience look-ups on the Part 21 data model: instances by id, records by entity name,
//! typed views of parameters, and the dangling-reference check.

use super::{Exchange, Instance, Param, Record};

impl Exchange {
    /// The instance `#id`, if the file defines it.
    #[must_use]
    pub fn get(&self, id: u64) -> Option<&Instance> {
        self.instances.get(&id)
    }

    /// Instances whose (simple) record or one of whose (complex) records is named `name`
    /// (case-insensitive), in id order.
    pub fn instances_of<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Instance> + 'a {
        self.instances
            .values()
            .filter(move |i| i.record(name).is_some())
    }

    /// References to ids the file does not define: `(referring instance id, missing id)`, in
    /// the order of the referring ids, then of the parameters.
    #[must_use]
    pub fn dangling_refs(&self) -> Vec<(u64, u64)> {
        let mut out = Vec::new();
        let mut stack: Vec<&Param> = Vec::new();
        for inst in self.instances.values() {
            for rec in &inst.records {
                stack.extend(rec.params.iter().rev());
                while let Some(p) = stack.pop() {
                    match p {
                        Param::Ref(id) if !self.instances.contains_key(id) => {
                            out.push((inst.id, *id))
                        }
                        Param::List(items) => stack.extend(items.iter().rev()),
                        Param::Typed(_, inner) => stack.push(inner),
                        _ => {}
                    }
                }
            }
        }
        out
    }
}

impl Instance {
    /// The record named `name` (case-insensitive): the record of a simple instance if it has
    /// that name, or the part of a complex instance with that name.
    #[must_use]
    pub fn record(&self, name: &str) -> Option<&Record> {
        self.records
            .iter()
            .find(|r| r.name.eq_ignore_ascii_case(name))
    }

    /// The record of a simple instance; `None` for a complex one.
    #[must_use]
    pub fn simple(&self) -> Option<&Record> {
        if self.complex {
            None
        } else {
            self.records.first()
        }
    }

    /// The entity name of a simple instance (`None` for a complex one).
    #[must_use]
    pub fn name(&self) -> Option<&str> {
        self.simple().map(|r| r.name.as_str())
    }
}

impl Record {
    /// Parameter `i` (0-based).
    #[must_use]
    pub fn param(&self, i: usize) -> Option<&Param> {
        self.params.get(i)
    }
}

impl Param {
    /// The referenced id of `#id`.
    #[must_use]
    #[allow(
        clippy::should_implement_trait,
        reason = "Part 21 vocabulary: an entity reference"
    )]
    pub fn as_ref(&self) -> Option<u64> {
        match self {
            Param::Ref(id) => Some(*id),
            _ => None,
        }
    }

    /// The value of a number: an integer or a real, also when wrapped in a typed parameter
    /// such as `LENGTH_MEASURE(1.5)`.
    #[must_use]
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            // Integers up to 2^53 convert exactly; beyond that rounding is the best answer.
            #[allow(
                clippy::cast_precision_loss,
                reason = "documented rounding for huge integers"
            )]
            Param::Integer(i) => Some(*i as f64),
            Param::Real(r) => Some(*r),
            Param::Typed(_, inner) => inner.as_f64(),
            _ => None,
        }
    }

    /// The value of an integer (also inside a typed parameter).
    #[must_use]
    pub fn as_i64(&self) -> Option<i64> {
        match self {
            Param::Integer(i) => Some(*i),
            Param::Typed(_, inner) => inner.as_i64(),
            _ => None,
        }
    }

    /// The items of an aggregate `( ... )`.
    #[must_use]
    pub fn as_list(&self) -> Option<&[Param]> {
        match self {
            Param::List(items) => Some(items),
            _ => None,
        }
    }

    /// The name of an enumeration value (without dots, upper case).
    #[must_use]
    pub fn as_enum(&self) -> Option<&str> {
        match self {
            Param::Enum(e) => Some(e),
            _ => None,
        }
    }

    /// The decoded text of a string.
    #[must_use]
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Param::String(s) => Some(s),
            _ => None,
        }
    }

    /// A boolean or logical `.T.` / `.F.`; `None` for `.U.` and anything else.
    #[must_use]
    pub fn as_bool(&self) -> Option<bool> {
        match self.as_enum() {
            Some("T") => Some(true),
            Some("F") => Some(false),
            _ => None,
        }
    }

    /// The type name and value of a typed parameter `NAME(value)`.
    #[must_use]
    pub fn as_typed(&self) -> Option<(&str, &Param)> {
        match self {
            Param::Typed(name, inner) => Some((name, inner)),
            _ => None,
        }
    }

    /// True for `$`.
    #[must_use]
    pub fn is_unset(&self) -> bool {
        matches!(self, Param::Unset)
    }
}
