//! The axial kernel: spans on which every active term is a forward-differenced, non-turbulent
//! trilinear term whose lattice step along the span has one nonzero axis (`axis`), and no term is
//! evaluated per pixel: the peers' plane and any unrotated plane aligned with the lattice.
//!
//! Every term's cell polynomial is then linear (`axis`), so the merged state is two words for the
//! value (and three for the gradients: `gx` is the slope itself). Each term is a [`Lane`]: its
//! countdown to its next cell event, its pixels in the current cell, its lattice coordinate
//! along the moving axis and its face blends, in a short array walked once per segment; a
//! segment ends when a countdown reaches zero, and every lane whose countdown is zero there (the
//! octaves' cell boundaries coincide on such planes) takes its event in the same pass, before the
//! next segment's pixel pass. There is no generic event search, no per-term strategy or
//! polynomial vector, and the pixel passes are the linear ones (`passes`), chosen once per span.
//!
//! Exactness: the lanes make the same state updates as the merged loop (`linear_sub` at the exit
//! pixel, `AxisFaces::enter` and `linear_add` at the entry, the lattice coordinate
//! `u0 + i du` in wrapping `i32`), in the same order of terms, so the samples and the counters
//! are the merged loop's (tested against `Direct`, `fd_at` through the merged loop, and the
//! lean shape, which does not compile this kernel).

use super::*;

/// One term of the axial kernel.
#[derive(Clone, Copy, Debug)]
struct Lane {
    /// Pixels before the term's next cell event (at least 1 while the span lasts).
    left: u32,
    /// Pixels since the term entered its current cell.
    l: u32,
    /// The moving axis (0..=2).
    k: usize,
    /// The lattice coordinate along `k` at pixel 0 of the span, and its step a pixel.
    u0: i32,
    d: i32,
    /// The lattice step across the span.
    dy: [i32; 3],
    /// The current cell and fractions (the two axes other than `k` never change).
    cell: [u16; 3],
    frac: [u32; 3],
    /// The blends of the current cell's faces `c_k = 0` and `c_k = 1` (`axis::face`).
    faces: [Face; 2],
    /// The current cell's polynomial (linear: `g[2] = g[3] = h[2] = 0`).
    poly: CubicPoly,
    hash: HashKind,
    amp: i32,
    /// Gradients for this term.
    g: bool,
}

impl Lane {
    /// The blend of face `b` of the current cell.
    #[inline(always)]
    fn blend(&self, b: usize, fv: u32, vb: u32) -> Face {
        let k = self.k.min(2); // always 0..=2: lets the compiler drop the bounds checks
        let w = face_bits(k, self.hash, self.cell, b, self.amp, fv, vb);
        face(&w, k, self.frac, self.dy, self.g)
    }

    /// The current cell's polynomial from its face blends.
    #[inline(always)]
    fn poly(&self) -> CubicPoly {
        poly(&self.faces, self.k, self.frac, self.d, self.dy, self.g)
    }
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// Whether the axial kernel takes the span: every active term forward-differenced (`Fd`,
    /// `Fd32`: the merged loop steps both exactly) with a single-axis step; `merged_takes` has
    /// already accepted the span (every such term trilinear, not turbulent).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn axial_takes(&self, setup: &Setup<T>, strategies: &[Strategy; T]) -> bool {
        let mut any = false;
        for (st, ts) in strategies.iter().zip(setup.terms.iter()) {
            match st {
                Strategy::Off => {}
                Strategy::Fd | Strategy::Fd32 if single_axis(ts.du).is_some() => any = true,
                _ => return false,
            }
        }
        any
    }

    /// The axial kernel over a span of `len` pixels with gradients (see the module
    /// documentation; without gradients the lane kernel takes the span); the span must have
    /// been accepted by `merged_takes` and [`Self::axial_takes`].
    #[inline(never)]
    pub(super) fn run_axial(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        sink: &mut ChunkSink<'_, '_>,
    ) {
        let m = self.model;
        let terms = m.terms();
        let fv = m.noise_frac_bits();
        let vb = m.precision().value_bits();
        let grads = GRADIENTS && self.opts.gradients;
        // Never taken: `run_merged` sends the spans without gradients to the lane kernel. The
        // early return tells the compiler that the rest of the function has gradients, so the
        // kernel's branches on them fold.
        if !grads {
            return;
        }
        let len = u32::from(len);
        let qc = setup.quadric().quad.c;
        let affine = qc[2] == 0 && setup.quadric().gqx[1] == 0 && setup.quadric().gqy[1] == 0;
        let mut quad = QuadStep::new(setup);

        let mut lanes: heapless::Vec<Lane, T> = heapless::Vec::new();
        let mut sum = Cubic::default();
        let mut grad_terms: u64 = 0;
        for ((term, st), ts) in terms.iter().zip(strategies).zip(setup.terms.iter()) {
            if *st == Strategy::Off {
                continue;
            }
            let Some(k) = single_axis(ts.du) else {
                continue;
            };
            let k = k.min(2);
            let g = grads && ts.gradient;
            grad_terms += u64::from(g);
            let (cell, frac) = split(ts.u0);
            let d = ts.du[k];
            let mut lane = Lane {
                left: pixels_in_cell_axis(frac[k], d),
                l: 0,
                k,
                u0: ts.u0[k],
                d,
                dy: ts.dy,
                cell,
                frac,
                faces: [Face::default(); 2],
                poly: CubicPoly::default(),
                hash: term.basis.hash,
                amp: ts.amp,
                g,
            };
            lane.faces = [lane.blend(0, fv, vb), lane.blend(1, fv, vb)];
            lane.poly = lane.poly();
            linear_add(&mut sum, &lane.poly, g);
            // At most T terms: never full.
            let _ = lanes.push(lane);
        }
        let mut setups = lanes.len() as u64;

        let mut i = 0u32;
        loop {
            let seg = lanes.iter().fold(len - i, |s, t| s.min(t.left));
            let mut left = seg as usize;
            while left > 0 {
                let n = left.min(sink.room());
                let at = sink.chunk.len;
                let c = &mut sink.chunk;
                if let Some(out) = c.f.get_mut(at..at + n) {
                    value_pass_linear(out, fv, &mut sum.p, &mut quad, affine);
                }
                if grads {
                    if let (Some(ox), Some(oy)) =
                        (c.gx.get_mut(at..at + n), c.gy.get_mut(at..at + n))
                    {
                        grad_pass_for(ox, fv, &mut sum.gx, &mut quad.gx, quad.dgx, affine);
                        grad_pass_for(oy, fv, &mut sum.gy, &mut quad.gy, quad.dgy, affine);
                    }
                }
                sink.advance(n);
                left -= n;
            }
            i += seg;
            if i >= len {
                break;
            }
            for t in lanes.iter_mut() {
                t.left -= seg;
                t.l += seg;
                if t.left != 0 {
                    continue;
                }
                let (k, g) = (t.k.min(2), t.g);
                linear_sub(&mut sum, &t.poly, t.l, g);
                let uk = t.u0.wrapping_add(t.d.wrapping_mul(i as i32));
                let cell = (uk >> 16) as u16;
                let step = match t.cell.get(k) {
                    Some(&c) => cell.wrapping_sub(c),
                    None => 0,
                };
                if let (Some(c), Some(f)) = (t.cell.get_mut(k), t.frac.get_mut(k)) {
                    *c = cell;
                    *f = (uk & 0xFFFF) as u32;
                }
                // Into the neighbouring cell along k: the shared face is kept (`AxisFaces`).
                t.faces = match step {
                    1 => [t.faces[1], t.blend(1, fv, vb)],
                    0xFFFF => [t.blend(0, fv, vb), t.faces[0]],
                    _ => [t.blend(0, fv, vb), t.blend(1, fv, vb)],
                };
                t.poly = t.poly();
                linear_add(&mut sum, &t.poly, g);
                t.l = 0;
                t.left = pixels_in_cell_axis((uk & 0xFFFF) as u32, t.d);
                setups += 1;
            }
        }

        let px = u64::from(len);
        let st = &mut self.stats;
        st.cell_setups += setups;
        st.noise_evaluations += px * lanes.len() as u64;
        if grads {
            st.gradient_evaluations += px * (1 + grad_terms);
        }
        st.fd_pixels += px;
        #[cfg(test)]
        {
            self.axial_spans += 1;
        }
    }
}

/// One term of the axial kernel's per-pixel form (`Direct`): its cell's face blends and its
/// fraction along the moving axis, advanced a pixel at a time.
#[derive(Clone, Copy, Debug)]
struct DirectLane {
    /// Pixels before the term's next cell event.
    left: u32,
    k: usize,
    u0: i32,
    d: i32,
    dy: [i32; 3],
    cell: [u16; 3],
    frac: [u32; 3],
    faces: [Face; 2],
    hash: HashKind,
    amp: i32,
}

impl DirectLane {
    #[inline(always)]
    fn blend(&self, b: usize, fv: u32, vb: u32) -> Face {
        let k = self.k.min(2); // always 0..=2: lets the compiler drop the bounds checks
        let w = face_bits(k, self.hash, self.cell, b, self.amp, fv, vb);
        face(&w, k, self.frac, self.dy, false)
    }
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// Whether the per-pixel axial kernel takes the span: no gradients, every active term
    /// evaluated per pixel (`Direct`), not turbulent, with a single-axis step; `merged_takes` has
    /// already accepted the span (every such term trilinear).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn axial_direct_takes(&self, setup: &Setup<T>, strategies: &[Strategy; T]) -> bool {
        if GRADIENTS && self.opts.gradients {
            return false;
        }
        let mut any = false;
        for ((st, ts), term) in strategies
            .iter()
            .zip(setup.terms.iter())
            .zip(self.model.terms())
        {
            match st {
                Strategy::Off => {}
                Strategy::Direct if !term.turbulence && single_axis(ts.du).is_some() => any = true,
                _ => return false,
            }
        }
        any
    }

    /// The per-pixel axial kernel: every term evaluated at every pixel from its cell's two face
    /// blends, `Phi_0 2^16 + (Phi_1 - Phi_0) f_k` (exactly `noise::value::interpolate`, see
    /// `AxisFaces::value_at`), the faces hashed and blended once per cell (the shared face
    /// kept), cell events found by counting down per term as in [`Self::run_axial`]. The samples
    /// and counters are the merged loop's per-pixel path's.
    #[inline(never)]
    pub(super) fn run_axial_direct(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        sink: &mut super::lanes::LaneOut<'_, '_, '_>,
    ) {
        let m = self.model;
        let fv = m.noise_frac_bits();
        let vb = m.precision().value_bits();
        let len = u32::from(len);
        let qc = setup.quadric().quad.c;
        let affine = qc[2] == 0;
        let (mut qq, mut dq, ddq) = (
            qc[0] as i64,
            qc[1].wrapping_add(qc[2]) as i64,
            qc[2].wrapping_mul(2) as i64,
        );
        let noq = qq == 0 && dq == 0 && ddq == 0;
        let mut lanes: heapless::Vec<DirectLane, T> = heapless::Vec::new();
        for ((term, st), ts) in m.terms().iter().zip(strategies).zip(setup.terms.iter()) {
            if *st == Strategy::Off {
                continue;
            }
            let Some(k) = single_axis(ts.du) else {
                continue;
            };
            let k = k.min(2);
            let (cell, frac) = split(ts.u0);
            let d = ts.du[k];
            let mut lane = DirectLane {
                left: pixels_in_cell_axis(frac[k], d),
                k,
                u0: ts.u0[k],
                d,
                dy: ts.dy,
                cell,
                frac,
                faces: [Face::default(); 2],
                hash: term.basis.hash,
                amp: ts.amp,
            };
            lane.faces = [lane.blend(0, fv, vb), lane.blend(1, fv, vb)];
            // At most T terms: never full.
            let _ = lanes.push(lane);
        }
        let nd = lanes.len() as u64;
        let fvs = fv & 31;
        let mut acc = [0i64; SAMPLE_CHUNK];
        let mut i = 0u32;
        loop {
            let seg = lanes.iter().fold(len - i, |s, t| s.min(t.left));
            let mut left = seg as usize;
            let mut j = i;
            while left > 0 {
                let n = left.min(sink.room(1)).min(SAMPLE_CHUNK);
                let (Some((out, _)), Some(acc)) = (sink.slots(n), acc.get_mut(..n)) else {
                    break;
                };
                if n == 0 {
                    break;
                }
                // Each term's values over the run (its fraction steps by `d` inside the cell).
                for (lane, t) in lanes.iter().enumerate() {
                    let fk0 = t.u0.wrapping_add(t.d.wrapping_mul(j as i32)) & 0xFFFF;
                    let base = t.faces[0].phi() << 16;
                    let dphi = wsub(t.faces[1].phi(), t.faces[0].phi());
                    let mut fk = i64::from(fk0);
                    let d = i64::from(t.d);
                    if lane == 0 {
                        for a in acc.iter_mut() {
                            *a = wadd(base, wmul(dphi, fk));
                            fk += d;
                        }
                    } else {
                        for a in acc.iter_mut() {
                            *a = wadd(*a, wadd(base, wmul(dphi, fk)));
                            fk += d;
                        }
                    }
                }
                for (o, &a) in out.iter_mut().zip(acc.iter()) {
                    let f = if noq {
                        (a >> (fvs + 32)) as i32
                    } else {
                        (qq.wrapping_add(a >> fvs) >> 32) as i32
                    };
                    *o = TexValue::from_bits(f);
                    if !noq {
                        qq = qq.wrapping_add(dq);
                        if !affine {
                            dq = dq.wrapping_add(ddq);
                        }
                    }
                }
                sink.advance(n);
                left -= n;
                j += n as u32;
            }
            i += seg;
            if i >= len {
                break;
            }
            for t in lanes.iter_mut() {
                t.left -= seg;
                if t.left != 0 {
                    continue;
                }
                let k = t.k.min(2);
                let uk = t.u0.wrapping_add(t.d.wrapping_mul(i as i32));
                let cell = (uk >> 16) as u16;
                let step = match t.cell.get(k) {
                    Some(&c) => cell.wrapping_sub(c),
                    None => 0,
                };
                if let (Some(c), Some(f)) = (t.cell.get_mut(k), t.frac.get_mut(k)) {
                    *c = cell;
                    *f = (uk & 0xFFFF) as u32;
                }
                t.faces = match step {
                    1 => [t.faces[1], t.blend(1, fv, vb)],
                    0xFFFF => [t.blend(0, fv, vb), t.faces[0]],
                    _ => [t.blend(0, fv, vb), t.blend(1, fv, vb)],
                };
                t.left = pixels_in_cell_axis((uk & 0xFFFF) as u32, t.d);
            }
        }
        let px = u64::from(len);
        let st = &mut self.stats;
        st.cell_setups += px * nd;
        st.noise_evaluations += px * nd;
        #[cfg(test)]
        {
            self.axial_spans += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::format::{Amplitude, MatrixEntry, QuadricCoeff};
    use crate::model::Octaves;
    use crate::noise::NoiseBasis;
    use crate::quadric::Quadric;
    use crate::transform::Affine3;

    /// Samples, counters and axial spans of `span`, in the fast or the size-lean shape.
    fn go<const T: usize>(
        m: &TextureModel<T>,
        opts: EvalOptions,
        span: &Span,
        lean: bool,
    ) -> (Vec<Sample>, SpanStats, u64) {
        let mut ev = SpanEvaluator::new(m, opts);
        ev.core.lean = lean;
        let mut out = Vec::new();
        ev.eval(span, |s| out.push(s));
        (out, *ev.stats(), ev.core.axial_spans)
    }

    /// [`SpanEvaluator::eval_values`] of `span` into a slice `extra` values longer than the span
    /// (filled with a marker), in the fast or the size-lean shape: the values, the counters and
    /// the axial spans; the marker past the span is checked untouched.
    fn values<const T: usize>(
        m: &TextureModel<T>,
        opts: EvalOptions,
        span: &Span,
        lean: bool,
    ) -> (Vec<TexValue>, SpanStats, u64) {
        let mut ev = SpanEvaluator::new(m, opts);
        ev.core.lean = lean;
        let marker = TexValue::from_bits(0x5A5A_5A5A);
        let mut out = std::vec![marker; usize::from(span.len) + 3];
        let info = ev.eval_values(span, &mut out);
        assert_eq!(info.extra_width48, ev.extra_width48(span));
        assert_eq!(out.split_off(usize::from(span.len)), [marker; 3]);
        assert_eq!(ev.options(), opts, "the options are restored");
        (out, *ev.stats(), ev.core.axial_spans)
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(160))]
        /// Unrotated octaves on a span along one lattice axis (the axial kernel): the samples are
        /// `Direct`'s, and the samples and counters are the merged loop's (the lean shape does
        /// not compile the kernel): any start, step (short and long cells, steps past a cell a
        /// pixel with culling off), length, gradients on and off, `mod` and `clamp`, zero,
        /// affine and curved quadrics, `Fd`, `Fd32` (exact where the merged loop takes the span,
        /// otherwise its 32-bit accumulators) and `Auto`; and the lane kernel's values are the
        /// merged axial kernel's.
        #[test]
        fn axial_kernel_is_direct(
            s0 in proptest::array::uniform3(-4_000_000i32..4_000_000),
            step in -90_000i32..90_000,
            axis in 0usize..3,
            dy in proptest::array::uniform3(-9_000i32..9_000),
            len in 0u16..400,
            clamp: bool,
            quadric in 0u32..3,
            gradients: bool,
            cull: bool,
            octaves in 1u8..6,
            zoom in 0u32..4,
            mode in 0usize..3,
        ) {
            let q = match quadric {
                0 => Quadric::ZERO,
                1 => Quadric::linear(
                    QuadricCoeff::ONE,
                    QuadricCoeff::ZERO,
                    QuadricCoeff::from_num(0.5),
                    QuadricCoeff::ZERO,
                ),
                _ => Quadric::from_f64([0.7, 0.1, 0.0, -0.2, 0.3, 0.0, 0.05, 1.1, 0.25, 0.4])
                    .unwrap(),
            };
            let wrap = if clamp { TableWrap::Clamp } else { TableWrap::Mod };
            let mut m: TextureModel<8> = TextureModel::new(q, wrap);
            m.push_octaves(&Octaves {
                count: octaves,
                base: Affine3::scale(MatrixEntry::from_num(1u32 << zoom)),
                amplitude: Amplitude::from_num(0.6),
                rotate: false,
                basis: NoiseBasis::trilinear(HashKind::Integer),
                turbulence: false,
            })
            .unwrap();
            let mut ds = [0; 3];
            ds[axis] = (step >> (2 * zoom)) | 1;
            let span = Span {
                s0: TexPoint::from_bits(s0[0], s0[1], s0[2]),
                ds: TexPoint::from_bits(ds[0], ds[1], ds[2]),
                dsdy: TexPoint::from_bits(dy[0], dy[1], dy[2]),
                len,
            };
            let opts = |mode| EvalOptions { mode, gradients, cull, ..Default::default() };
            let opts_g = |mode, gradients| EvalOptions { mode, gradients, cull, ..Default::default() };
            let mode = [EvalMode::Fd, EvalMode::Fd32, EvalMode::Auto][mode];
            let (direct, direct_st, direct_axial) = go(&m, opts(EvalMode::Direct), &span, false);
            // `Direct` in the per-pixel axial kernel (no gradients) and in the merged loop (lean).
            let (lean_direct, lean_direct_st, _) = go(&m, opts(EvalMode::Direct), &span, true);
            proptest::prop_assert_eq!(&direct, &lean_direct);
            proptest::prop_assert_eq!(direct_st, lean_direct_st);
            if !(GRADIENTS && gradients) && len > 0 && FD && !clamp && quadric == 0 {
                let active = direct_st.noise_evaluations > 0;
                proptest::prop_assert_eq!(direct_axial, u64::from(active));
            }
            let (fast, fast_st, axial) = go(&m, opts(mode), &span, false);
            let (lean, lean_st, lean_axial) = go(&m, opts(mode), &span, true);
            // `Fd32` is exact where the merged loop (and so the axial kernel) takes the span.
            if mode != EvalMode::Fd32 || fast_st.fd_pixels == 0 || axial == 1 {
                proptest::prop_assert_eq!(&fast, &direct);
            }
            proptest::prop_assert_eq!(&fast, &lean);
            proptest::prop_assert_eq!(fast_st, lean_st);
            proptest::prop_assert_eq!(lean_axial, 0);
            // Without gradients the lane kernel (`lanes`) takes the span, with them the merged
            // axial kernel: the same values.
            let f_of = |g: bool| -> Vec<TexValue> {
                go(&m, opts_g(mode, g), &span, false).0.iter().map(|s| s.f).collect()
            };
            proptest::prop_assert_eq!(f_of(false), f_of(true));
            // `eval_values` writes the same values in both shapes and every mode, counts what
            // `eval` without gradients counts, and takes the lane kernel where `eval` does.
            for m_ in [mode, EvalMode::Direct] {
                let (plain, plain_st, plain_axial) = go(&m, opts_g(m_, false), &span, false);
                let plain: Vec<TexValue> = plain.iter().map(|s| s.f).collect();
                for lean in [false, true] {
                    let (v, st, ax) = values(&m, opts(m_), &span, lean);
                    proptest::prop_assert_eq!(&v, &plain);
                    proptest::prop_assert_eq!(st, plain_st);
                    proptest::prop_assert_eq!(ax, if lean { 0 } else { plain_axial });
                }
            }
            // `Fd` on a span the merged loop takes is the axial kernel's.
            let resolved = (step >> zoom).unsigned_abs() < NYQUIST_STEP as u32;
            if mode == EvalMode::Fd && len > 0 && FD && !clamp && quadric == 0 && resolved {
                proptest::prop_assert_eq!(axial, 1);
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
        /// Rows of an axis-aligned plane through face caches of several sizes (one of them
        /// shared with a second model, evaluated row by row in between) give the values of
        /// `eval_values` without a cache, and `Direct`'s: whatever the rows step along (the
        /// cached blend's axis or the other one), the start, the zoom and the octaves.
        #[test]
        fn face_caches_change_no_value(
            s0 in proptest::array::uniform3(-4_000_000i32..4_000_000),
            step in 1i32..40_000,
            row in -9_000i32..9_000,
            axis in 0usize..3,
            across in 1usize..3,
            octaves in 1u8..6,
            zoom in 0u32..3,
            len in 1u16..300,
            clamp: bool,
        ) {
            let wrap = if clamp { TableWrap::Clamp } else { TableWrap::Mod };
            let model = |amp: f64, hash| super::super::lanes::tests::model(octaves, zoom, amp, hash, wrap);
            let (m1, m2) = (model(0.6, HashKind::Integer), model(-0.35, HashKind::default()));
            let other = (axis + across) % 3;
            let mut ds = [0; 3];
            ds[axis] = step >> (2 * zoom) | 1;
            let mut dy = [0; 3];
            dy[other] = row;
            let span = |y: i32| Span {
                s0: TexPoint::from_bits(
                    s0[0].wrapping_add(dy[0].wrapping_mul(y)),
                    s0[1].wrapping_add(dy[1].wrapping_mul(y)),
                    s0[2].wrapping_add(dy[2].wrapping_mul(y)),
                ),
                ds: TexPoint::from_bits(ds[0], ds[1], ds[2]),
                dsdy: TexPoint::from_bits(dy[0], dy[1], dy[2]),
                len,
            };
            let opts = |mode| EvalOptions { mode, gradients: false, cull: true, ..Default::default() };
            let mut c1 = FaceCache::<1>::new();
            let mut c4 = FaceCache::<4>::new();
            let mut c64 = FaceCache::<64>::new();
            let mut c256 = FaceCache::<256>::new();
            let mut evs: std::vec::Vec<_> =
                (0..5).map(|_| SpanEvaluator::new(&m1, opts(EvalMode::Fd))).collect();
            let mut other_ev = SpanEvaluator::new(&m2, opts(EvalMode::Fd));
            let mut direct = SpanEvaluator::new(&m1, opts(EvalMode::Direct));
            let n = usize::from(len);
            for y in 0..12 {
                let sp = span(y);
                let mut want = std::vec![TexValue::ZERO; n];
                direct.eval_values(&sp, &mut want);
                let mut got = std::vec![std::vec![TexValue::ZERO; n]; 5];
                evs[0].eval_values(&sp, &mut got[0]);
                evs[1].eval_values_cached(&sp, &mut got[1], &mut c1);
                evs[2].eval_values_cached(&sp, &mut got[2], &mut c4);
                evs[3].eval_values_cached(&sp, &mut got[3], &mut c64);
                evs[4].eval_values_cached(&sp, &mut got[4], &mut c256);
                for (i, g) in got.iter().enumerate() {
                    proptest::prop_assert_eq!(g, &want, "evaluator {} row {}", i, y);
                }
                // The second model through the same 64-entry cache.
                let mut a = std::vec![TexValue::ZERO; n];
                let mut b = std::vec![TexValue::ZERO; n];
                other_ev.eval_values_cached(&sp, &mut a, &mut c64);
                SpanEvaluator::new(&m2, opts(EvalMode::Direct)).eval_values(&sp, &mut b);
                proptest::prop_assert_eq!(a, b, "second model row {}", y);
            }
            for ev in &evs[1..] {
                proptest::prop_assert_eq!(ev.stats(), evs[0].stats());
            }
        }
    }

    #[test]
    fn peers_plane_rows_take_the_axial_kernel() {
        use crate::texture::workload::peers;
        for w in [
            peers::Workload::Value1,
            peers::Workload::Value4,
            peers::Workload::Value4Grad,
        ] {
            let m = peers::model(w, HashKind::Integer).unwrap();
            let opts = |mode| EvalOptions {
                mode,
                gradients: w.gradients(),
                cull: true,
                ..Default::default()
            };
            for y in [0, 5, 201] {
                let span = peers::span(y, 0, peers::SIZE);
                let (d, _, _) = go(&m, opts(EvalMode::Direct), &span, false);
                let (f, _, axial) = go(&m, opts(EvalMode::Fd), &span, false);
                assert_eq!(f, d, "{w:?} row {y}");
                assert_eq!(axial, u64::from(FD), "{w:?}");
            }
        }
    }
}
