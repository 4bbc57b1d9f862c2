//! ISO 10303-21 (Part 21) exchange-structure reader.
