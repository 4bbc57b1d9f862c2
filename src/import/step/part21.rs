//! ISO 10303-21 (Part 21) exchange-structure reader: header, data sections, simple and complex
//! entity instances, parameters. Tolerant of what real files contain; never panics or hangs on
//! what malformed ones contain.
//!
//! Entry point: [`parse`]. Look-ups: [`Exchange::get`], [`Instance::record`], [`Param::as_ref`],
//! [`Param::as_f64`], [`Param::as_list`], [`Exchange::dangling_refs`] and friends.
//!
//! Accepted with a [`Diagnostic`] (what real writers produce): lower-case keywords, several
//! DATA sections (one id space), Edition 3 `DATA(...)` headers and SIGNATURE sections, a
//! missing `END-ISO-10303-21;` or text after it, a malformed header entity (Open CASCADE reads
//! such files too), raw UTF-8 or invalid bytes inside strings (decoded lossily), backslashes
//! that start no control directive, typed parameters wrapped in dots (`.LENGTH_MEASURE(1.).`).
//! Accepted silently as unambiguous: reals written `.5`, `1e3`, `+2.`; a byte-order mark.
//!
//! Refused with a [`Part21Error`] naming the line and the `#id` being read: anything truncated
//! (inside a record, string, comment or DATA section), unbalanced parentheses, a missing `;`,
//! duplicate ids (naming both lines; Open CASCADE refuses these), non-finite or overflowing
//! numbers (`1E999999`), non-Part 21 numbers (`1.0D0`, `1_000.`), integers beyond `i64`,
//! `#-1` or `#abc` names, string literals longer than [`MAX_STRING_BYTES`], aggregates nested
//! deeper than [`MAX_DEPTH`], bytes that are not Part 21 text outside strings. Whether a
//! reference points to an existing instance is the caller's business ([`Exchange::dangling_refs`]).
//!
//! Resources: one pass, no per-token allocation (tokens borrow the input), recursion bounded by
//! [`MAX_DEPTH`], at most [`MAX_WARNINGS`] diagnostics; memory is proportional to the input, as
//! every instance needs at least 7 bytes of text (`#1=A();`).

mod accessors;
mod lexer;
mod parser;
mod text;

use std::collections::BTreeMap;

use crate::diagnostics::Diagnostic;

pub use lexer::MAX_STRING_BYTES;
pub use parser::{MAX_DEPTH, MAX_WARNINGS};

/// Parses a Part 21 exchange structure from its bytes.
///
/// # Errors
/// A [`Part21Error`] with the 1-based line (and the `#id` being read, inside DATA) when the
/// bytes are not a readable exchange structure.
pub fn parse(bytes: &[u8]) -> Result<Exchange, Part21Error> {
    parser::Parser::new(bytes).exchange()
}

/// One parameter value of an entity record.
#[derive(Clone, Debug, PartialEq)]
pub enum Param {
    /// `$`: no value.
    Unset,
    /// `*`: value derived (redeclared attribute).
    Derived,
    /// An integer.
    Integer(i64),
    /// A real number (always finite).
    Real(f64),
    /// A string, escapes decoded.
    String(String),
    /// An enumeration value without the dots, e.g. `T`, `F`, `UNSPECIFIED`.
    Enum(String),
    /// A reference `#id`.
    Ref(u64),
    /// A binary value (hex digits as written).
    Binary(String),
    /// An aggregate `( ... )`.
    List(Vec<Param>),
    /// A typed parameter `NAME(value)`, e.g. `LENGTH_MEASURE(1.)`.
    Typed(String, Box<Param>),
}

/// One entity record: `NAME(params)`. A complex instance has several.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// Entity type name, upper case.
    pub name: String,
    /// Parameters in order.
    pub params: Vec<Param>,
}

/// An entity instance `#id = ...;`.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// The instance id.
    pub id: u64,
    /// 1-based line where the instance starts.
    pub line: usize,
    /// The record (simple instance) or records (complex instance, in file order).
    pub records: Vec<Record>,
    /// True for a complex instance `( A(...) B(...) )`.
    pub complex: bool,
}

/// The header section.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Header {
    /// `FILE_DESCRIPTION` description strings.
    pub description: Vec<String>,
    /// `FILE_NAME` name.
    pub name: String,
    /// `FILE_NAME` originating system.
    pub originating_system: String,
    /// `FILE_SCHEMA` schema identifiers.
    pub schema: Vec<String>,
}

/// A parsed exchange structure.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Exchange {
    /// Header.
    pub header: Header,
    /// Instances by id.
    pub instances: BTreeMap<u64, Instance>,
    /// Problems tolerated while reading (with their line/#id).
    pub diagnostics: Vec<Diagnostic>,
}

/// A Part 21 syntax or structure error.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("line {line}{}: {message}", id.map(|i| format!(", #{i}")).unwrap_or_default())]
pub struct Part21Error {
    /// 1-based line.
    pub line: usize,
    /// The instance being read, when known.
    pub id: Option<u64>,
    /// What is wrong.
    pub message: String,
}
