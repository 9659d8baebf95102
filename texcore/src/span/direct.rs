//! Trilinear terms evaluated per pixel inside the merged loop (`EvalMode::Direct`, and `Auto`
//! where cells are too short to forward-difference): the corners are hashed once per cell; a
//! pixel evaluates the cell's monomial form (`noise::value::CellPoly`), or, for a single-axis
//! term without gradients, the linear form of its two face blends (`axis`; the shared face kept
//! across cells). Both are exactly `noise::value::interpolate` (tested through the span's
//! `Direct` against `Fd` and the reference tests).

use super::*;

/// A trilinear term evaluated per pixel inside the merged loop: its lattice position, and the
/// monomial form of its current cell with the derivatives along and across the span, rebuilt
/// only when the term enters a new cell (the corners are hashed once per cell, not per pixel).
pub(super) struct DirectTerm {
    pub(super) u: [i32; 3],
    pub(super) du: [i32; 3],
    pub(super) dy: [i32; 3],
    /// The cell `poly` belongs to, once `entered` (not an `Option`: with every byte defined the
    /// term's set-up stores no undefined bytes, which the compiler copied through `memcpy`).
    pub(super) cell: [u16; 3],
    pub(super) entered: bool,
    pub(super) poly: CellPoly,
    pub(super) along: CellDirection,
    pub(super) across: CellDirection,
    pub(super) hash: HashKind,
    pub(super) amp: i32,
    pub(super) neg: bool,
    pub(super) turbulence: bool,
    pub(super) grads: bool,
    /// The moving axis of a single-axis term without gradients: its value is then the face
    /// blends' linear form at the pixel (`axis`), the shared face kept across cells.
    pub(super) axis: Option<usize>,
    pub(super) faces: AxisFaces,
}

impl DirectTerm {
    /// Value and gradients at the current pixel (exactly [`crate::noise::value::interpolate`] and
    /// [`crate::noise::value::directional`]), then one step along the span.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn sample(&mut self, fv: u32, vb: u32) -> (i64, i64, i64) {
        let (cell, frac) = split(self.u);
        if let Some(k) = self.axis {
            let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
            if !self.entered || self.cell != cell {
                let (hash, amp) = (self.hash, self.amp);
                self.faces.blend(cell, frac, k, self.dy, false, |c, b| {
                    face_bits(k, hash, c, b, amp, fv, vb)
                });
                self.cell = cell;
                self.entered = true;
            }
            let mut p = self.faces.value_at(frac[k]);
            if self.turbulence && ((p < 0) != self.neg) {
                p = p.wrapping_neg();
            }
            self.u = [
                self.u[0].wrapping_add(self.du[0]),
                self.u[1].wrapping_add(self.du[1]),
                self.u[2].wrapping_add(self.du[2]),
            ];
            return (p, 0, 0);
        }
        if !self.entered || self.cell != cell {
            let v = scaled_corners_bits(self.hash, cell, self.amp, fv, vb);
            self.poly = CellPoly::new(&v);
            if self.grads {
                self.along = self.poly.direction(self.du);
                self.across = self.poly.direction(self.dy);
            }
            self.cell = cell;
            self.entered = true;
        }
        let mut p = self.poly.value(frac);
        let (mut a, mut b) = if self.grads {
            (
                CellPoly::directional(&self.along, frac),
                CellPoly::directional(&self.across, frac),
            )
        } else {
            (0, 0)
        };
        if self.turbulence && ((p < 0) != self.neg) {
            p = p.wrapping_neg();
            a = a.wrapping_neg();
            b = b.wrapping_neg();
        }
        self.u = [
            self.u[0].wrapping_add(self.du[0]),
            self.u[1].wrapping_add(self.du[1]),
            self.u[2].wrapping_add(self.du[2]),
        ];
        (p, a, b)
    }
}
