//! Colour-table antialiasing filters: summed-area colour table, colour-table MIP map, filter width.
