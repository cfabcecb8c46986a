//! persp (to be written)
