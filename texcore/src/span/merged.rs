//! The merged forward-difference loop: every forward-differenced term of the span is a
//! non-turbulent trilinear term and all of them share one accumulator set (see
//! [`SpanEvaluator::run_merged`]); cell events subtract a leaving term's state and add the new
//! cell's. Per-span plan: which terms are merged, which are evaluated per pixel, which loop shape.

use super::*;

impl<'m, const T: usize> EvalCore<'m, T> {
    /// Whether [`Self::run_merged`] takes a span of `len` pixels with these strategies: every
    /// active term a cubic, forward differenced (not turbulent) or per pixel, and (clamp tables,
    /// gradients) the quadric's sums below 2^62. Below 2^62 the quadric and its gradients plus
    /// the noise (|N| <= 2^61, gradients below 2^59 after `>> fv`) can never saturate, so the
    /// merged pixel loop adds with plain wrapping additions; `mod` tables wrap `q` by definition.
    pub(super) fn merged_takes(
        &self,
        len: u32,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
    ) -> bool {
        let m = self.model;
        let accepted = m.terms().iter().zip(strategies).all(|(term, st)| match st {
            Strategy::Off => true,
            Strategy::Fd | Strategy::Fd32 => term.basis.is_cubic() && !term.turbulence,
            Strategy::Direct => term.basis.is_cubic(),
            _ => false,
        });
        let grads = GRADIENTS && self.opts.gradients;
        accepted
            && (m.wrap() != TableWrap::Clamp || fits(&setup.quadric().quad.c, len))
            && (!grads || (fits(&setup.quadric().gqx, len) && fits(&setup.quadric().gqy, len)))
    }

    /// The fast path: every forward-differenced term is a non-turbulent trilinear term, and their
    /// forward differences are merged into **one** accumulator set (a sum of cubics is a cubic
    /// while no term changes cell; wrapping arithmetic keeps it exact). Per pixel that is three
    /// 64-bit additions for the value and four for the two gradients, whatever the number of
    /// terms. When a term leaves its cell, its state at that pixel is subtracted (evaluated from
    /// its polynomial, [`fd_at`]) and the new cell's added ([`cubic_poly`]). Terms evaluated
    /// per pixel (`Direct`, trilinear only) are added on top. The quadric and its gradients are
    /// stepped in i64, which is exact when they provably stay in range over the span (checked
    /// here; `mod` tables only need `q` modulo 2^64). Returns `false`, having emitted nothing,
    /// when the span needs the general loop.
    ///
    /// Exactness of the merged gradient: every trilinear term's derivative inside its cell is at
    /// most `3 * 2^48 * max|v'|` per pixel step of at most half a cell (terms past Nyquist have no
    /// gradient), and `sum_k max|v'_k| <= 2^13 + T` (model 4.4), so the sum stays below 2^63 and
    /// the general loop's saturating sum never saturates: wrapping and saturating sums agree.
    pub(super) fn run_merged(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        sink: &mut ChunkSink<'_, '_>,
    ) -> bool {
        let m = self.model;
        let lean = self.lean();
        let terms = m.terms();
        let fv = m.noise_frac_bits();
        let vb = m.precision().value_bits();
        let grads = GRADIENTS && self.opts.gradients;
        let len = u32::from(len);
        if !self.merged_takes(len, setup, strategies) {
            return false;
        }
        #[cfg(not(texcore_lean))]
        if !lean && self.axial_takes(setup, strategies) {
            if grads {
                self.run_axial(len as u16, setup, strategies, sink);
            } else {
                self.run_lanes_into(len as u16, setup, strategies, sink);
            }
            return true;
        }
        #[cfg(not(texcore_lean))]
        if !lean && self.axial_direct_takes(setup, strategies) {
            self.run_axial_direct_into(len as u16, setup, strategies, sink);
            return true;
        }
        let mut n_fd = 0usize;
        let mut n_direct = 0usize;
        for st in strategies.iter().take(terms.len()) {
            match st {
                Strategy::Fd | Strategy::Fd32 => n_fd += 1,
                Strategy::Direct => n_direct += 1,
                _ => {}
            }
        }
        let qc = setup.quadric().quad.c;
        // An affine quadric along the span (linear `q`, constant gradients) skips three additions.
        let affine = qc[2] == 0 && setup.quadric().gqx[1] == 0 && setup.quadric().gqy[1] == 0;
        let mut quad = QuadStep::new(setup);

        // Merged terms: their polynomials, entry pixel and exit pixel.
        // (Vectors, not arrays: nothing is written for the slots a span does not use.)
        let mut merged: heapless::Vec<(usize, CubicPoly, u32, u32), T> = heapless::Vec::new();
        // Per merged term: its moving axis when its lattice step has one (the cell set-up of
        // `axis`), and the blends of its cell's faces.
        let mut faces: heapless::Vec<(Option<usize>, AxisFaces), T> = heapless::Vec::new();
        let mut direct: heapless::Vec<DirectTerm, T> = heapless::Vec::new();
        let mut sum = Cubic::default();
        let mut setups: u64 = 0;
        let mut grad_terms: u64 = 0;
        for (k, ((term, st), ts)) in terms
            .iter()
            .zip(strategies)
            .zip(setup.terms.iter())
            .enumerate()
        {
            if *st != Strategy::Off && grads && ts.gradient {
                grad_terms += 1;
            }
            match st {
                Strategy::Fd | Strategy::Fd32 => {
                    let g = grads && ts.gradient;
                    let (cell, frac) = split(ts.u0);
                    let (hash, amp) = (term.basis.hash, ts.amp);
                    setups += 1;
                    let ax = single_axis(ts.du);
                    let mut af = AxisFaces::default();
                    let poly = match ax {
                        Some(a) => af.enter(cell, frac, a, ts.du, ts.dy, g, |c, b| {
                            face_bits(a, hash, c, b, amp, fv, vb)
                        }),
                        None => {
                            let v = scaled_corners_bits(hash, cell, amp, fv, vb);
                            cubic_poly(&v, frac, ts.du, ts.dy, g)
                        }
                    };
                    let exit = match ax {
                        Some(a) => {
                            linear_add(&mut sum, &poly, g);
                            pixels_in_cell_axis(frac[a.min(2)], ts.du[a.min(2)])
                        }
                        None => {
                            sum.add(&fd_start(&poly, g));
                            pixels_in_cell(frac, ts.du)
                        }
                    };
                    // At most T terms: never full.
                    let _ = merged.push((k, poly, 0, exit));
                    let _ = faces.push((ax, af));
                }
                Strategy::Direct => {
                    let (amp, neg) = amp_and_sign(term, ts);
                    let _ = direct.push(DirectTerm {
                        u: ts.u0,
                        du: ts.du,
                        cell: [0; 3],
                        entered: false,
                        poly: CellPoly::default(),
                        along: CellDirection::default(),
                        across: CellDirection::default(),
                        hash: term.basis.hash,
                        amp,
                        neg,
                        turbulence: term.turbulence,
                        grads: grads && ts.gradient,
                        dy: ts.dy,
                        axis: single_axis(ts.du).filter(|_| !(grads && ts.gradient)),
                        faces: AxisFaces::default(),
                    });
                }
                _ => {}
            }
        }
        let (nm, nd) = (merged.len(), direct.len());
        debug_assert_eq!((nm, nd), (n_fd, n_direct));

        let mut i = 0u32;
        while i < len {
            let end = merged.iter().fold(len, |e, t| e.min(t.3));
            let seg = end - i;
            if !lean && nd == 0 && seg >= PASS_MIN {
                // Component passes over the chunk: value, then each gradient.
                let mut left = seg as usize;
                while left > 0 {
                    let k = left.min(sink.room());
                    let at = sink.chunk.len;
                    let c = &mut sink.chunk;
                    if let Some(out) = c.f.get_mut(at..at + k) {
                        value_pass_for(out, fv, &mut sum.p, &mut quad, affine);
                    }
                    if grads {
                        if let (Some(ox), Some(oy)) =
                            (c.gx.get_mut(at..at + k), c.gy.get_mut(at..at + k))
                        {
                            grad_pass_for(ox, fv, &mut sum.gx, &mut quad.gx, quad.dgx, affine);
                            grad_pass_for(oy, fv, &mut sum.gy, &mut quad.gy, quad.dgy, affine);
                        }
                    }
                    sink.advance(k);
                    left -= k;
                }
            } else if !lean && nd == 0 {
                // Short segments (cells of a few pixels): one fused pass costs less than three.
                pixel_loop(
                    lean,
                    seg,
                    fv,
                    grads,
                    affine,
                    &mut sum,
                    &mut quad,
                    &mut |smp: Sample| sink.push(smp),
                    |_, _, _| {},
                );
            } else {
                let direct = &mut direct;
                pixel_loop(
                    lean,
                    seg,
                    fv,
                    grads,
                    affine,
                    &mut sum,
                    &mut quad,
                    &mut |smp: Sample| sink.push(smp),
                    |n: &mut i64, gx: &mut i64, gy: &mut i64| {
                        for t in direct.iter_mut() {
                            let (p, a, b) = t.sample(fv, vb);
                            *n = n.wrapping_add(p);
                            *gx = gx.wrapping_add(a);
                            *gy = gy.wrapping_add(b);
                        }
                    },
                );
            }
            i = end;
            if i >= len {
                break;
            }
            for ((k, poly, start, next), (ax, af)) in merged.iter_mut().zip(faces.iter_mut()) {
                if *next != i {
                    continue;
                }
                let (Some(term), Some(ts)) = (terms.get(*k), setup.terms.get(*k)) else {
                    continue;
                };
                let g = grads && ts.gradient;
                let l = i - *start;
                match *ax {
                    // A linear cell polynomial: its state is two words (four with gradients).
                    Some(_) => linear_sub(&mut sum, poly, l, g),
                    None => sum.sub(&fd_at(poly, l, g)),
                }
                let at = i as i32;
                let u = [
                    ts.u0[0].wrapping_add(ts.du[0].wrapping_mul(at)),
                    ts.u0[1].wrapping_add(ts.du[1].wrapping_mul(at)),
                    ts.u0[2].wrapping_add(ts.du[2].wrapping_mul(at)),
                ];
                let (cell, frac) = split(u);
                let (hash, amp) = (term.basis.hash, ts.amp);
                setups += 1;
                *poly = match *ax {
                    Some(a) => af.enter(cell, frac, a, ts.du, ts.dy, g, |c, b| {
                        face_bits(a, hash, c, b, amp, fv, vb)
                    }),
                    None => {
                        let v = scaled_corners_bits(hash, cell, amp, fv, vb);
                        cubic_poly(&v, frac, ts.du, ts.dy, g)
                    }
                };
                *start = i;
                match *ax {
                    Some(a) => {
                        linear_add(&mut sum, poly, g);
                        *next =
                            i.saturating_add(pixels_in_cell_axis(frac[a.min(2)], ts.du[a.min(2)]));
                    }
                    None => {
                        sum.add(&fd_start(poly, g));
                        *next = i.saturating_add(pixels_in_cell(frac, ts.du));
                    }
                }
            }
        }

        let px = u64::from(len);
        let st = &mut self.stats;
        st.cell_setups += setups + px * nd as u64;
        st.noise_evaluations += px * (nm + nd) as u64;
        if grads {
            st.gradient_evaluations += px * (1 + grad_terms);
        }
        if nm > 0 {
            st.fd_pixels += px;
        }
        true
    }
}
