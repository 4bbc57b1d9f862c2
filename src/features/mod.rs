//! Machining features recognised on a B-rep (L1): the regions a 2.5D strategy machines
//! ([`regions`]: pockets, steps, slots, the top and the outer profile seen from +Z).

pub mod regions;
