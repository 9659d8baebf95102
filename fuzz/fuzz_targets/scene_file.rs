//! Scene-file loader: any text is either a scene or a [`host_sim::scenefile::SceneFileError`]
//! (never a panic); a loaded scene's first and last frames build their scene and materials and
//! render at a tiny size. Memory stays bounded by the loader's limits (libFuzzer's
//! `-rss_limit_mb` fails the run otherwise).
#![no_main]

use host_sim::scenefile;
use host_sim::scenes::render_host_frame;
use host_sim::unit::UnitConfig;
use libfuzzer_sys::fuzz_target;
use texcore::hash::HashKind;
use texcore::render::Output;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(mut scene) = scenefile::parse(text, "fuzz.toml") else {
        return;
    };
    // Render small: the file's own size may be up to the format's limit.
    scene.scene.camera.width = scene.scene.camera.width.min(8);
    scene.scene.camera.height = scene.scene.camera.height.min(6);
    let last = scene.scene.frames().max(1) - 1;
    for frame in [0, last] {
        for hash in [HashKind::Integer, HashKind::Permutation] {
            scene
                .frame(frame, hash)
                .expect("a loaded scene builds every frame's materials");
        }
        let cfg = UnitConfig::default();
        render_host_frame(&scene, frame, &cfg, HashKind::Integer, Output::Color)
            .expect("a loaded scene renders");
    }
});
