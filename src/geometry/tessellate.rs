//! Tessellation of surfaces and trimmed faces to a chord tolerance, with normals.
