//! splitter (to be written)
