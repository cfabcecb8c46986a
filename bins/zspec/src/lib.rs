//! zspec (to be written)
