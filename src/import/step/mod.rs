//! STEP (ISO 10303-21, AP203/AP214/AP242) import: a tolerant Part 21 reader ([`part21`]) and the
//! B-rep builder that maps entities to Talas geometry ([`brep`]).

pub mod brep;
pub mod part21;
