//! The general loop: one strategy per term (direct, cached cell, exact or 32-bit forward
//! differences, Hermite segments), for every span the merged loop does not take. Exact modes
//! give the same samples as the merged loop and as direct evaluation.

use super::*;

impl<'m, const T: usize> EvalCore<'m, T> {
    /// The evaluation loop, each term's strategy from the mode (`strategy`).
    pub(super) fn run(&mut self, len: u16, setup: &Setup<T>, sink: &mut ChunkSink<'_, '_>) {
        let mode = compiled_mode(self.opts.mode);
        let m = self.model;
        let fv = m.noise_frac_bits();
        let vb = m.precision().value_bits();
        let wrap = m.wrap();
        let grads = GRADIENTS && self.opts.gradients;
        let terms = m.terms();
        // A model holds at most T terms; `min` lets the compiler see it (no bounds checks).
        let n = terms.len().min(T);

        // The plan, as `plan` makes it, written out: through `plan` the size-lean probes grow by
        // 36 to 42 bytes of texcore `.text`.
        let mut strategies = [Strategy::Off; T];
        for ((st, ts), term) in strategies.iter_mut().zip(setup.terms.iter()).zip(terms) {
            if ts.active {
                *st = strategy(mode, ts, term.basis.is_cubic(), len);
                // Without the general loop's forward differencing, turbulent cubic terms are
                // evaluated per pixel, which the merged loop does (identical samples).
                if !GENERAL_FD && *st == Strategy::Fd && term.turbulence {
                    *st = Strategy::Direct;
                }
            }
        }
        // Without forward differencing every term is `Direct` or `Cached`: the general loop. The
        // size-lean shape leaves the merged loop out when the general loop forward-differences.
        if FD && !(GENERAL_FD && self.lean()) && self.run_merged(len, setup, &strategies, sink) {
            return;
        }
        // The size-lean shape without the merged loop: where the merged loop would have taken
        // the span, it would have stepped `Fd32`'s terms exactly; so does the general loop.
        if FD && GENERAL_FD && self.lean() && self.merged_takes(u32::from(len), setup, &strategies)
        {
            for st in strategies.iter_mut() {
                if *st == Strategy::Fd32 {
                    *st = Strategy::Fd;
                }
            }
        }

        // A vector, not an array: only the model's terms are initialised. Each run is pushed as
        // one literal of scalars and zeros ([`TermRun::start`]): a default run set field by
        // field before or after the push was built beside the vector and copied into it (a
        // zeroing and two copies, one unaligned, about 290 instructions a term on the M4F).
        let mut runs: heapless::Vec<TermRun, T> = heapless::Vec::new();
        for (ts, st) in setup.terms.iter().zip(strategies.iter()).take(n) {
            let strategy = match (ts.active, *st) {
                (false, _) => Strategy::Off,
                // Exact either way: per pixel is the direct computation.
                (true, Strategy::Fd) if !GENERAL_FD => Strategy::Direct,
                (true, s) => s,
            };
            let u = if ts.active { ts.u0 } else { [0; 3] };
            let remaining = if strategy == Strategy::Direct {
                u32::MAX
            } else {
                0
            };
            // At most T terms: never full.
            let _ = runs.push(TermRun::start(strategy, u, remaining));
        }

        // Quadric forward differences (exact, wrapping i128); a model without a quadric (no
        // nonzero matrix entry) skips them.
        let quad_zero = self.qmask == 0;
        let qc = setup.quadric().quad.c;
        let mut q = qc[0];
        let mut dq = qc[1].wrapping_add(qc[2]);
        let ddq = qc[2].wrapping_mul(2);
        let mut gqx = setup.quadric().gqx[0];
        let mut gqy = setup.quadric().gqy[0];

        let len = u32::from(len);
        let mut i = 0u32;
        while i < len {
            // (Re-)anchor every term whose segment ended; the segment is the shortest of them.
            let mut seg = len - i;
            for ((r, ts), term) in runs.iter_mut().zip(setup.terms.iter()).zip(terms) {
                // Without strategies that keep state, every term is `Off` or `Direct` (never
                // re-anchored).
                if !GENERAL_ANCHORS || r.strategy == Strategy::Off {
                    continue;
                }
                if r.remaining == 0 {
                    let (amp, _) = amp_and_sign(term, ts);
                    let (cell, frac) = split(r.u);
                    if !r.cached || cell != r.cell {
                        r.data = term.basis.cell_bits(cell, amp, fv, vb);
                        r.cell = cell;
                        r.cached = true;
                        self.stats.cell_setups += 1;
                    }
                    let in_cell = pixels_in_cell(frac, ts.du);
                    // Unused when only the cell cache keeps state.
                    #[allow(unused_variables)]
                    let want_g = grads && ts.gradient;
                    r.remaining = match (r.strategy, &r.data) {
                        #[cfg(feature = "turbulence-fd")]
                        (Strategy::Fd, CellData::Value(v)) => {
                            r.fd = cubic_setup(v, frac, ts, want_g);
                            in_cell
                        }
                        #[cfg(feature = "fd32")]
                        (Strategy::Fd32, CellData::Value(v)) => {
                            r.fd32 = narrow(&cubic_setup(v, frac, ts, want_g));
                            in_cell.min(FD32_ANCHOR)
                        }
                        #[cfg(texcore_hermite)]
                        (Strategy::Hermite, data) => {
                            // At most a quarter of a cell along the span, at most 16 pixels.
                            let step = ts.du.iter().map(|d| d.unsigned_abs()).max().unwrap_or(0);
                            let quarter = (1u32 << 14) / step.max(1);
                            let l = in_cell
                                .min(HERMITE_SEGMENT)
                                .min(quarter.max(2))
                                .min(len - i);
                            r.fd = hermite_setup(term, data, r.u, ts, l, amp, fv, want_g);
                            l
                        }
                        _ => in_cell,
                    };
                }
                seg = seg.min(r.remaining);
            }

            for _ in 0..seg {
                let mut nsum: i64 = 0;
                let mut gxn: i64 = 0;
                let mut gyn: i64 = 0;
                // Never set when no forward-difference strategy is compiled in.
                #[allow(unused_mut)]
                let mut any_fd = false;
                for ((r, ts), term) in runs.iter_mut().zip(setup.terms.iter()).zip(terms) {
                    let (amp, neg) = amp_and_sign(term, ts);
                    let want_g = grads && ts.gradient;
                    let (mut v, mut gx, mut gy) = match r.strategy {
                        Strategy::Off => continue,
                        // A Hermite segment steps like a cubic (its `gy[2]` is zero).
                        #[cfg(texcore_fd_state)]
                        Strategy::Fd | Strategy::Hermite => {
                            any_fd = true;
                            let c = &mut r.fd;
                            let out = (c.p[0], c.gx[0], c.gy[0]);
                            c.p[0] = c.p[0].wrapping_add(c.p[1]);
                            c.p[1] = c.p[1].wrapping_add(c.p[2]);
                            c.p[2] = c.p[2].wrapping_add(c.p[3]);
                            if want_g {
                                c.gx[0] = c.gx[0].wrapping_add(c.gx[1]);
                                c.gx[1] = c.gx[1].wrapping_add(c.gx[2]);
                                c.gy[0] = c.gy[0].wrapping_add(c.gy[1]);
                                c.gy[1] = c.gy[1].wrapping_add(c.gy[2]);
                            }
                            out
                        }
                        #[cfg(feature = "fd32")]
                        Strategy::Fd32 => {
                            any_fd = true;
                            let c = &mut r.fd32;
                            let out = (
                                i64::from(c.p[0]) << 32,
                                i64::from(c.gx[0]) << 32,
                                i64::from(c.gy[0]) << 32,
                            );
                            c.p[0] = c.p[0].wrapping_add(c.p[1]);
                            c.p[1] = c.p[1].wrapping_add(c.p[2]);
                            c.p[2] = c.p[2].wrapping_add(c.p[3]);
                            if want_g {
                                c.gx[0] = c.gx[0].wrapping_add(c.gx[1]);
                                c.gx[1] = c.gx[1].wrapping_add(c.gx[2]);
                                c.gy[0] = c.gy[0].wrapping_add(c.gy[1]);
                                c.gy[1] = c.gy[1].wrapping_add(c.gy[2]);
                            }
                            out
                        }
                        #[cfg(any(
                            feature = "smooth-fade",
                            feature = "gradient-noise",
                            feature = "mnoise"
                        ))]
                        Strategy::Cached => {
                            let (_, frac) = split(r.u);
                            eval_term(term, &r.data, frac, ts, amp, fv, want_g)
                        }
                        Strategy::Direct => {
                            let (cell, frac) = split(r.u);
                            let data = term.basis.cell_bits(cell, amp, fv, vb);
                            self.stats.cell_setups += 1;
                            eval_term(term, &data, frac, ts, amp, fv, want_g)
                        }
                        // Strategies that are not compiled in are never chosen.
                        #[allow(unreachable_patterns)]
                        _ => continue,
                    };
                    if term.turbulence {
                        if v < 0 {
                            v = v.wrapping_neg();
                            gx = gx.wrapping_neg();
                            gy = gy.wrapping_neg();
                        }
                        if neg {
                            v = v.wrapping_neg();
                            gx = gx.wrapping_neg();
                            gy = gy.wrapping_neg();
                        }
                    }
                    nsum = nsum.wrapping_add(v);
                    if want_g {
                        gxn = gxn.saturating_add(gx);
                        gyn = gyn.saturating_add(gy);
                        self.stats.gradient_evaluations += 1;
                    }
                    self.stats.noise_evaluations += 1;
                    r.u = [
                        r.u[0].wrapping_add(ts.du[0]),
                        r.u[1].wrapping_add(ts.du[1]),
                        r.u[2].wrapping_add(ts.du[2]),
                    ];
                    r.remaining = r.remaining.saturating_sub(1);
                    if r.strategy == Strategy::Direct {
                        r.remaining = u32::MAX;
                    }
                }
                if any_fd {
                    self.stats.fd_pixels += 1;
                }

                let f = combine(wrap, if quad_zero { 0 } else { q }, nsum, fv);
                let sample = if grads {
                    self.stats.gradient_evaluations += 1;
                    Sample {
                        f,
                        gx: sat_i64(gqx).saturating_add(gxn >> fv),
                        gy: sat_i64(gqy).saturating_add(gyn >> fv),
                    }
                } else {
                    Sample { f, gx: 0, gy: 0 }
                };
                sink.push(sample);

                if !quad_zero {
                    q = q.wrapping_add(dq);
                    dq = dq.wrapping_add(ddq);
                }
                if grads {
                    gqx = gqx.wrapping_add(setup.quadric().gqx[1]);
                    gqy = gqy.wrapping_add(setup.quadric().gqy[1]);
                }
            }
            i += seg;
        }
    }
}
