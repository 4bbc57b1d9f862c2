//! Checks on tool paths (L3): surface analysis for tool choice, local and rear gouge detection
//! against the exact surface, and the independent scallop/gouge verification used by the tests.
