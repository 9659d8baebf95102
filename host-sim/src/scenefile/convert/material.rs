//! Materials: a preset or a custom model (noise terms, quadric, colour keys), each value
//! range-checked and converted once.

use super::*;

pub(super) fn hash(h: HashDef) -> HashKind {
    match h {
        HashDef::Perm => HashKind::Permutation,
        HashDef::Int => HashKind::Integer,
    }
}

pub(super) fn basis(b: Option<&S<BasisDef>>) -> BasisKind {
    match b.map(|b| *b.get_ref()) {
        None | Some(BasisDef::Value) => BasisKind::Value,
        Some(BasisDef::Gradient) => BasisKind::Gradient,
        Some(BasisDef::Mnoise) => BasisKind::Modified,
    }
}

pub(super) fn fade(f: Option<&S<FadeDef>>) -> Fade {
    match f.map(|f| *f.get_ref()) {
        None | Some(FadeDef::Linear) => Fade::Linear,
        Some(FadeDef::Smooth) => Fade::Smooth,
        Some(FadeDef::Quintic) => Fade::Quintic,
    }
}

pub(super) fn amplitude_value(v: Option<&S<f64>>, field: &str) -> R<Amplitude> {
    match v {
        None => Ok(Amplitude::ONE),
        Some(a) => {
            let x = real(a, field, |x| x.abs() <= AMPLITUDE_MAX, "|amplitude| <= 512")?;
            Ok(Amplitude::from_bits(q16(x) as i32))
        }
    }
}

pub(super) fn keys(v: &S<Vec<KeyDef>>, field: &str) -> R<Vec<Key>> {
    let list = v.get_ref();
    if list.is_empty() {
        return fail(v.span(), field, "at least one colour key is needed");
    }
    if list.len() > texcore::ready::MAX_KEYS {
        return fail(
            v.span(),
            field,
            format!(
                "{} colour keys given, at most {} allowed",
                list.len(),
                texcore::ready::MAX_KEYS
            ),
        );
    }
    let mut out: Vec<Key> = Vec::with_capacity(list.len());
    for (i, k) in list.iter().enumerate() {
        let (p, c) = k.get_ref();
        let f = format!("{field}[{i}]");
        let x = real(p, &f, |x| (0.0..=1.0).contains(&x), "0 <= position <= 1")?;
        let pos = q16(x) as u32;
        if let Some(prev) = out.last() {
            if pos < prev.0 {
                return fail(
                    p.span(),
                    f,
                    format!(
                        "position {} is before the previous key's ({}): keys must be in order",
                        number(x),
                        number(f64::from(prev.0) / 65536.0)
                    ),
                );
            }
        }
        out.push((pos, colour(c, &f)?));
    }
    Ok(out)
}

pub(super) fn material(name: &str, m: &S<MaterialDef>, field: &str) -> R<MaterialFx> {
    let d = m.get_ref();
    let preset = match &d.preset {
        Some(p) => {
            let known = texcore::presets::NAMES;
            match known.iter().find(|n| **n == p.get_ref().as_str()) {
                Some(n) => Some(*n),
                None => {
                    return fail(
                        p.span(),
                        format!("{field}.preset"),
                        format!(
                            "unknown preset `{}` (known: {})",
                            p.get_ref(),
                            known.join(", ")
                        ),
                    )
                }
            }
        }
        None => None,
    };
    let perturbed = preset.is_some_and(|p| p.starts_with("mn-"));
    if perturbed {
        let model_field = [
            ("quadric", d.quadric.as_ref().map(|v| v.span())),
            (
                "noise",
                d.noise.as_ref().and_then(|v| v.first()).map(|v| v.span()),
            ),
            (
                "octaves",
                d.octaves.as_ref().and_then(|v| v.first()).map(|v| v.span()),
            ),
            ("phase", d.phase.as_ref().map(|v| v.span())),
            (
                "phase_direction",
                d.phase_direction.as_ref().map(|v| v.span()),
            ),
        ];
        for (f, span) in model_field {
            if let Some(span) = span {
                return fail(
                    span,
                    format!("{field}.{f}"),
                    format!(
                        "preset `{}` is a perturbed material, not a quadric-plus-noise model: it has no {f}",
                        preset.unwrap_or("")
                    ),
                );
            }
        }
    }
    let amplitude = match &d.amplitude {
        Some(a) => q16(real(
            a,
            &format!("{field}.amplitude"),
            |x| x.abs() <= AMPLITUDE_MAX,
            "|amplitude| <= 512",
        )?),
        None => 65536,
    };
    let phase = match &d.phase {
        Some(p) => q16(real(p, &format!("{field}.phase"), coord_ok, COORD_RANGE)?),
        None => 0,
    };
    let phase_direction = match &d.phase_direction {
        Some(v) => {
            let dir = coord3(v, &format!("{field}.phase_direction"))?;
            dir.map(|x| x as i32)
        }
        None => [0, 65536, 0],
    };
    let keys = match &d.keys {
        Some(k) => Some(&*Box::leak(
            keys(k, &format!("{field}.keys"))?.into_boxed_slice(),
        )),
        None if preset.is_none() => {
            return fail(
                m.span(),
                format!("{field}.keys"),
                "missing: a material without a preset needs colour keys",
            )
        }
        None => None,
    };
    let quadric = match &d.quadric {
        Some(q) => {
            let c = q.get_ref();
            if c.len() != 10 {
                return fail(
                    q.span(),
                    format!("{field}.quadric"),
                    format!(
                        "expected 10 coefficients [A, B, C, D, E, F, G, H, I, J], found {}",
                        c.len()
                    ),
                );
            }
            let mut out = [QuadricCoeff::ZERO; 10];
            for (k, x) in c.iter().enumerate() {
                if !x.is_finite() || !coord_ok(*x) {
                    return fail(
                        q.span(),
                        format!("{field}.quadric[{k}]"),
                        format!("{} is out of range ({COORD_RANGE})", number(*x)),
                    );
                }
                out[k] = QuadricCoeff::from_bits(q16(*x) as i32);
            }
            Some(Quadric::from_coefficients(out))
        }
        None => None,
    };
    let mut terms: Option<Vec<TermFx>> = None;
    let mut count = 0usize;
    if let Some(list) = &d.noise {
        let t = terms.get_or_insert_with(Vec::new);
        for (i, n) in list.iter().enumerate() {
            let f = format!("{field}.noise[{i}]");
            let nd = n.get_ref();
            count += 1;
            if count > TERMS_MAX {
                return fail(
                    n.span(),
                    f,
                    format!("a material has at most {TERMS_MAX} noise terms (octaves included)"),
                );
            }
            let (mm, tt) = affine(
                nd.scale.as_ref(),
                "scale",
                nd.matrix.as_ref(),
                nd.translate.as_ref(),
                &f,
            )?;
            t.push(TermFx::Noise {
                amplitude: amplitude_value(nd.amplitude.as_ref(), &format!("{f}.amplitude"))?,
                transform: to_affine(&mm, &tt),
                kind: basis(nd.basis.as_ref()),
                fade: fade(nd.fade.as_ref()),
                hash: nd.hash.as_ref().map(|h| hash(*h.get_ref())),
                turbulence: nd.turbulence.as_ref().is_some_and(|b| *b.get_ref()),
            });
        }
    }
    if let Some(list) = &d.octaves {
        let t = terms.get_or_insert_with(Vec::new);
        for (i, o) in list.iter().enumerate() {
            let f = format!("{field}.octaves[{i}]");
            let od = o.get_ref();
            let n = int(
                &od.count,
                &format!("{f}.count"),
                1,
                TERMS_MAX as i64,
                "count",
            )? as usize;
            count += n;
            if count > TERMS_MAX {
                return fail(
                    od.count.span(),
                    format!("{f}.count"),
                    format!("a material has at most {TERMS_MAX} noise terms (octaves included); this makes {count}"),
                );
            }
            let (mm, tt) = affine(
                od.frequency.as_ref(),
                "frequency",
                od.matrix.as_ref(),
                od.translate.as_ref(),
                &f,
            )?;
            t.push(TermFx::Octaves {
                count: n as u8,
                amplitude: amplitude_value(od.amplitude.as_ref(), &format!("{f}.amplitude"))?,
                base: to_affine(&mm, &tt),
                rotate: od.rotate.as_ref().is_some_and(|b| *b.get_ref()),
                kind: basis(od.basis.as_ref()),
                fade: fade(od.fade.as_ref()),
                hash: od.hash.as_ref().map(|h| hash(*h.get_ref())),
                turbulence: od.turbulence.as_ref().is_some_and(|b| *b.get_ref()),
            });
        }
    }
    Ok(MaterialFx {
        name: leak(name),
        preset,
        keys,
        squared_keys: d
            .key_spacing
            .as_ref()
            .map(|s| *s.get_ref() == SpacingDef::Squared),
        wrap: d.wrap.as_ref().map(|w| match *w.get_ref() {
            WrapDef::Mod => TableWrap::Mod,
            WrapDef::Clamp => TableWrap::Clamp,
        }),
        quadric,
        terms,
        hash: d.hash.as_ref().map(|h| hash(*h.get_ref())),
        amplitude,
        phase,
        phase_direction,
        span: m.span(),
        amplitude_span: d.amplitude.as_ref().map(|a| a.span()),
    })
}
