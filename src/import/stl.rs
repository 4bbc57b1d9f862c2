//! STL reader (ASCII and binary, reliably told apart) and writer.
