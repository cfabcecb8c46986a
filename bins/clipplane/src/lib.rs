//! clipplane (to be written)
