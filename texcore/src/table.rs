//! Colour tables: N entries (a power of two, 2 to 1024) built from key colours, looked up by `f`.
