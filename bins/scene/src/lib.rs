//! scene (to be written)
