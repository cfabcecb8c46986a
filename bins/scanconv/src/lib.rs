//! scanconv (to be written)
