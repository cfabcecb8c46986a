//! zbuf (to be written)
