//! Stock simulation (L4): dexel stock, material removal by the swept volume of the cutter,
//! surface extraction, deviation from the design part, collisions.
