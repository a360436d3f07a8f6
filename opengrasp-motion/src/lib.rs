//! placeholder overview, replaced by the crate's owner.
