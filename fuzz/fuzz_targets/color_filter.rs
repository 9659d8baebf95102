//! Colour filters: random tables (2, 16 or 256 entries), any table coordinate and any filter
//! width (zero, sub-entry, past the table's length, `U16F16::MAX`), both wraps and look-ups,
//! every antialiasing filter (none, MIP, csat, three-times-long csat), through `ColorStage` and
//! the filters' own entry points. Checks: no panic; every colour channel within the table's
//! range for that channel; `shade_each` equals `shade`; widths of the whole table or more give
//! the csat's table mean (`Csat3` in mod wrap too).
#![no_main]

use libfuzzer_sys::fuzz_target;
use texcore::color::Rgba8888;
use texcore::filter::{Antialias, ColorMip, ColorStage, Csat, Csat3};
use texcore::format::{FilterWidth, TableCoord, TexValue};
use texcore::table::{ColorTable, TableLookup, TableWrap};
use texcore_fuzz::Bytes;

fn channels(c: Rgba8888) -> [u8; 4] {
    [c.r, c.g, c.b, c.a]
}

/// Per-channel (min, max) of the entries.
fn range(entries: &[Rgba8888]) -> [(u8, u8); 4] {
    let mut r = [(u8::MAX, 0u8); 4];
    for e in entries {
        for (k, v) in channels(*e).into_iter().enumerate() {
            r[k] = (r[k].0.min(v), r[k].1.max(v));
        }
    }
    r
}

fn assert_in(c: Rgba8888, r: &[(u8, u8); 4], what: &str) {
    for (k, v) in channels(c).into_iter().enumerate() {
        assert!(
            r[k].0 <= v && v <= r[k].1,
            "{what}: channel {k} = {v} outside the table's {}..={}",
            r[k].0,
            r[k].1
        );
    }
}

fn width(b: &mut Bytes) -> FilterWidth {
    FilterWidth::from_bits(match b.below(4) {
        0 => b.u32(),
        1 => b.u32() >> (8 + b.below(24)),
        2 => u32::from(b.u16()) << 8,
        _ => u32::MAX - u32::from(b.u8()),
    })
}

fn run<const N: usize>(b: &mut Bytes) {
    let entries: [Rgba8888; N] = core::array::from_fn(|_| Rgba8888 {
        r: b.u8(),
        g: b.u8(),
        b: b.u8(),
        a: b.u8(),
    });
    let table = ColorTable::from_entries(entries).expect("power-of-two size");
    let r = range(&entries);
    let wrap = b.pick(&[TableWrap::Mod, TableWrap::Clamp]);
    let lookup = b.pick(&[TableLookup::Nearest, TableLookup::Linear]);
    let csat = Csat::new(&table);
    let csat3 = Csat3::new(&table, wrap);
    let mip = ColorMip::new(table);
    let stages = [
        Antialias::None,
        Antialias::Mip,
        Antialias::Csat,
        Antialias::Csat3,
    ]
    .map(|aa| ColorStage::new(table, wrap, lookup, aa).expect("every filter is compiled in"));
    let mut fs = Vec::new();
    let mut ws = Vec::new();
    while !b.is_empty() && fs.len() < 64 {
        let f = TexValue::from_bits(b.i32_scaled());
        let w = width(b);
        let x = TableCoord::from_bits(b.u32());
        for s in &stages {
            assert_in(
                s.shade(f, w),
                &r,
                &format!("{:?} shade({f:?}, {w:?})", s.antialias()),
            );
        }
        assert_in(csat.box_filter(x, w, wrap), &r, "Csat::box_filter");
        assert_in(csat3.box_filter(x, w), &r, "Csat3::box_filter");
        assert_in(mip.lookup(x, w, wrap, lookup), &r, "ColorMip::lookup");
        assert_in(
            mip.level_lookup(u32::from(b.u8()), x, wrap, lookup),
            &r,
            "ColorMip::level_lookup",
        );
        if u64::from(w.to_bits()) >= (N as u64) << 16 {
            assert_eq!(
                csat.box_filter(x, w, wrap),
                csat.mean(),
                "csat width {w:?} past the table"
            );
        }
        fs.push(f);
        ws.push(w);
    }
    for s in &stages {
        let mut each = Vec::new();
        s.shade_each(&fs, &ws, |c| each.push(c));
        let one: Vec<_> = fs.iter().zip(&ws).map(|(&f, &w)| s.shade(f, w)).collect();
        assert_eq!(
            each,
            one,
            "{:?}: shade_each differs from shade",
            s.antialias()
        );
    }
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes::new(data);
    match b.below(3) {
        0 => run::<2>(&mut b),
        1 => run::<16>(&mut b),
        _ => run::<256>(&mut b),
    }
});
