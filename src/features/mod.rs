//! Machining features read from the B-rep: what a part asks to be made, in the terms a shop uses
//! (holes with their diameters, depths and bottoms), found from the faces' exact surfaces rather
//! than from triangles. Strategies plan operations from these.

pub mod holes;
