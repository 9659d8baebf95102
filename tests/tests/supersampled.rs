//! Antialiasing against the supersampled truth (`texsim check SCENE --supersampled N`,
//! `host_sim::truth`) on every built-in scene and animation at a reduced size: the filtered
//! image is at least as close to the truth as the unfiltered one, by at least 1 dB where the
//! scene recedes to a horizon, and no band of more than three rows is flat where the truth shows
//! texture; the flight towards the horizon (section 4.4) flickers less than the unfiltered
//! images and within the measured distance of its truth's flicker.

use host_sim::scenes::HostScene;
use host_sim::truth::{check, SupersampledReport};
use host_sim::unit::UnitConfig;
use texcore::hash::HashKind;

fn report(name: &str, w: u16, h: u16) -> SupersampledReport {
    report_with(name, w, h, &UnitConfig::default())
}

/// The still frame of `name` at `w x h` with the texture unit `cfg` against its 4 x 4 truth.
fn report_with(name: &str, w: u16, h: u16, cfg: &UnitConfig) -> SupersampledReport {
    let mut scene = HostScene::builtin(texcore::scene::by_name(name).unwrap());
    scene.scene.camera.width = w;
    scene.scene.camera.height = h;
    let frame = scene.scene.still();
    check(&scene, frame, cfg, HashKind::Permutation, 4).unwrap()
}

#[test]
fn filtered_images_are_closer_to_the_truth() {
    for name in texcore::scene::BUILTIN
        .iter()
        .chain(&texcore::scene::ANIMATIONS)
    {
        let name = *name;
        let (w, h) = if name == "zoneplate" {
            (128, 128)
        } else {
            (160, 120)
        };
        let r = report(name, w, h);
        eprintln!(
            "{name}: filtered {:.2} dB, unfiltered {:.2} dB (no culling {:.2}), 2x2 {:.2} dB, \
             4x4 {:.2} dB, flat band {}",
            r.psnr_filtered,
            r.psnr_unfiltered,
            r.psnr_unfiltered_no_cull,
            r.psnr_supersampled_2x2,
            r.psnr_supersampled_4x4,
            r.longest_flat_band
        );
        assert!(r.psnr_filtered.is_finite() && r.psnr_unfiltered.is_finite());
        // The scale: more samples a pixel come closer to the truth (the 4 x 4 truth here is
        // texcore's 4 x 4 but for fixed point and culling, so 4x4 is within a step of it).
        assert!(
            r.psnr_supersampled_4x4 >= r.psnr_supersampled_2x2
                && r.psnr_supersampled_2x2 >= r.psnr_unfiltered_no_cull - 0.5,
            "{name}: 2x2 {} 4x4 {} unfiltered (no culling) {}",
            r.psnr_supersampled_2x2,
            r.psnr_supersampled_4x4,
            r.psnr_unfiltered_no_cull
        );
        // Every scene, `fire` included (a clamp table's box is centred on the unclamped `f`:
        // measured +2.5 dB at this size, +3.3 dB at 320 x 240).
        assert!(
            r.psnr_filtered >= r.psnr_unfiltered,
            "{name}: filtered {} < unfiltered {}",
            r.psnr_filtered,
            r.psnr_unfiltered
        );
        // Where the scene recedes to a horizon the filter gains: at this reduced size and 4 x 4
        // truth the seascape by 0.65 dB (1 dB is the goal at full size), the moonrise by more.
        if matches!(name, "moonrise" | "seascape" | "flight") {
            assert!(r.gain_db >= 0.5, "{name}: gain {}", r.gain_db);
        }
        // No more than three flat rows (the fade floor of 1/4; with 1/8 the seascape kept five
        // at this size, six at 320 x 240). At this half size the seascape's view (seascape,
        // flight) keeps four just below its horizon; at its own size one (next test).
        let band = if matches!(name, "seascape" | "flight") {
            4
        } else {
            3
        };
        assert!(
            r.longest_flat_band <= band,
            "{name}: {}",
            r.longest_flat_band
        );
    }
}

/// The seascape at its own size (320 x 240, against a 4 x 4 truth): at most three rows flat
/// below the horizon where the truth shows texture (measured: one; six with the fade floor of
/// 1/8), and the filter's gain (0.97 dB against this 4 x 4 truth, 1.19 dB against the 8 x 8 one
/// of `texsim check seascape --supersampled 8`, where the goal of 1 dB is set).
#[test]
fn the_seascape_keeps_its_texture_to_the_horizon_at_its_own_size() {
    let r = report("seascape", 320, 240);
    eprintln!("{r:?}");
    assert!(r.longest_flat_band <= 3, "{r:?}");
    assert!(r.gain_db >= 0.9, "{r:?}");
}

/// The flight towards the horizon (Hart et al. 1999 section 4.4) over its first frames, at 80 x 60
/// against a 4 x 4 truth: the filter reduces the unfiltered images' flicker near the horizon
/// (the paper's observation) and stays within 1.5 times the truth's flicker (no aliasing). The
/// band is not frozen flat: measured 0.43 of the truth's flicker at this size (0.31 with the
/// fade `1 / L`), 0.68 at 320 x 240 (next test).
#[test]
fn the_flight_flickers_less_than_unfiltered_and_not_more_than_the_truth() {
    let mut scene = HostScene::builtin(texcore::scene::by_name("flight").unwrap());
    scene.scene.camera.width = 80;
    scene.scene.camera.height = 60;
    let f = host_sim::truth::flicker(
        &scene,
        0,
        4,
        &UnitConfig::default(),
        HashKind::Permutation,
        4,
    )
    .unwrap();
    eprintln!("{f:?}");
    assert_eq!((f.first, f.frames, f.rows), (0, 4, [23, 37]));
    assert!(f.flicker_truth > 0.1, "{f:?}");
    assert!(f.flicker_filtered < f.flicker_unfiltered, "{f:?}");
    assert!(f.ratio <= 1.5 && f.ratio >= 0.25, "{f:?}");
    let bad = host_sim::truth::flicker(
        &scene,
        0,
        1,
        &UnitConfig::default(),
        HashKind::Permutation,
        4,
    );
    assert!(bad.is_err());
}

/// Horizon flicker at the scenes' own size (320 x 240, frames 0 to 3, against a 4 x 4 truth):
/// the seascape's and the flight's filtered images flicker within 1.5 times the truth's and at
/// least 1/1.5 of it, neither aliasing nor frozen (measured 0.77 and 0.68; 0.66 and 0.55 with
/// the fade `1 / L` and the spread `1 - w/2`).
#[test]
fn horizon_flicker_is_within_one_and_a_half_times_the_truths() {
    for name in ["seascape", "flight"] {
        let scene = HostScene::builtin(texcore::scene::by_name(name).unwrap());
        let f = host_sim::truth::flicker(
            &scene,
            0,
            4,
            &UnitConfig::default(),
            HashKind::Permutation,
            4,
        )
        .unwrap();
        eprintln!("{name}: {f:?}");
        assert_eq!(f.rows, [90, 150], "{name}");
        assert!(f.flicker_truth > 0.1, "{name}: {f:?}");
        assert!(
            f.ratio >= 1.0 / 1.5 && f.ratio <= 1.5,
            "{name}: flicker {} against the truth's {} (ratio {})",
            f.flicker_filtered,
            f.flicker_truth,
            f.ratio
        );
    }
}

/// The zone plate (Hart et al. 1999, fig. 8): each colour-table filter's RMS error against the
/// supersampled truth is at most 0.6 times the unfiltered image's (a PSNR gain of at least
/// `20 log10(1 / 0.6)` = 4.44 dB; measured at 256 x 256: csat +20.3 dB, mip +16.3 dB).
#[test]
fn zone_plate_filters_cut_the_error_to_six_tenths() {
    use texcore::filter::Antialias;
    for aa in [Antialias::Csat, Antialias::Csat3, Antialias::Mip] {
        let cfg = UnitConfig {
            aa,
            ..UnitConfig::default()
        };
        let r = report_with("zoneplate", 128, 128, &cfg);
        let ratio = 10f64.powf(-(r.psnr_filtered - r.psnr_unfiltered) / 20.0);
        eprintln!(
            "zoneplate {aa:?}: filtered {:.2} dB, unfiltered {:.2} dB, error ratio {ratio:.3}",
            r.psnr_filtered, r.psnr_unfiltered
        );
        assert!(ratio <= 0.6, "{aa:?}: error ratio {ratio:.3}");
    }
}
