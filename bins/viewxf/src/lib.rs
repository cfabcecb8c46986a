//! viewxf (to be written)
