//! STEP entities → boundary representation.
