//! `texsim mesh pack` and `texsim atlas`.

use std::io::Write;

/// Prints a line to stdout, ignoring a closed pipe (never a panic).
macro_rules! out {
    ($($t:tt)*) => {{
        let _ = writeln!(std::io::stdout().lock(), $($t)*);
    }};
}
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Subcommand};
use texcore::scene::Mesh;

use super::view::{Orbit, Sampling, Source};
use super::{AtlasKind, Layout};
use crate::cli::{bad_input, KnobArgs};
use crate::mesh::{self, TriMesh};
use crate::output::{write_atomic, write_png, Frame, OutputError};

/// `texsim mesh ...`.
#[derive(Debug, Subcommand)]
pub enum MeshCommand {
    /// Validate a mesh file (.obj or .ply) and write texcore's packed device form.
    Pack(PackArgs),
}

/// `texsim mesh pack`.
#[derive(Clone, Debug, Args)]
pub struct PackArgs {
    /// Mesh file (.obj or .ply).
    pub mesh: PathBuf,
    /// Output file (the device links it with `include_bytes!`).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `texsim atlas`.
#[derive(Clone, Debug, Args)]
pub struct AtlasArgs {
    /// Mesh file (.obj or .ply), or a built-in mesh: `teapot`, `sphere`, `torus`.
    pub mesh: String,
    /// Layout.
    #[arg(long, value_enum, default_value_t = AtlasKind::Uniform)]
    pub kind: AtlasKind,
    /// Atlas side in texels.
    #[arg(long, default_value_t = 256)]
    pub size: u32,
    /// Gutter: 0 for nearest look-ups, 1 for bilinear and MIP (the default).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(0..=1))]
    pub gutter: u8,
    /// Material baked into the atlas (a preset name).
    #[arg(long, default_value = "marble")]
    pub material: String,
    /// Atlas image to write (PNG; unused texels loud magenta, transparent).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also draw the mesh from the atlas into this PNG.
    #[arg(long)]
    pub view: Option<PathBuf>,
    /// Look-up for --view.
    #[arg(long, value_enum, default_value_t = Sampling::Bilinear)]
    pub sampling: Sampling,
    /// Print the measures as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Accuracy knobs of the bake.
    #[command(flatten)]
    pub knobs: KnobArgs,
}

/// The built-in meshes by name (the teapot, sphere and torus of the built-in scenes).
pub fn builtin_mesh(name: &str) -> Option<TriMesh> {
    let m = match name {
        "teapot" => Mesh::Teapot { level: 5 },
        "sphere" => Mesh::Sphere {
            radius: 65536,
            stacks: 16,
            slices: 32,
        },
        "torus" => Mesh::Torus {
            major: 65536,
            minor: 65536 * 38 / 100,
            major_segments: 40,
            minor_segments: 16,
        },
        _ => return None,
    };
    let mut positions = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut triangles = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for t in m.triangles() {
        let tri = t.map(|p| {
            let key = (p.x, p.y, p.z);
            *index.entry(key).or_insert_with(|| {
                positions.push([
                    p.x as f64 / 65536.0,
                    p.y as f64 / 65536.0,
                    p.z as f64 / 65536.0,
                ]);
                positions.len() as u32 - 1
            })
        });
        let [a, b, c] = tri.map(|i| positions[i as usize]);
        // Sliver triangles of the tessellation (zero area after rounding) and repeats of a
        // patch seam are left out, as the loaders would refuse them.
        let mut key = tri;
        key.sort_unstable();
        if mesh::triangle_area(a, b, c) > 1e-12 * mesh::longest_edge(a, b, c).powi(2)
            && seen.insert(key)
        {
            triangles.push(tri);
        }
    }
    TriMesh::from_parts(name, positions, triangles).ok()
}

/// A mesh by file or built-in name.
pub fn load_mesh(name: &str) -> Result<TriMesh, String> {
    if let Some(m) = builtin_mesh(name) {
        return Ok(m);
    }
    let p = Path::new(name);
    if !p.exists() {
        return Err(format!(
            "{name}: no such mesh file (or built-in mesh: teapot, sphere, torus)"
        ));
    }
    mesh::load(p).map_err(|e| e.to_string())
}

/// Runs `texsim mesh`.
pub fn run_mesh(c: &MeshCommand) -> ExitCode {
    match c {
        MeshCommand::Pack(a) => {
            let m = match mesh::load(&a.mesh) {
                Ok(m) => m,
                Err(e) => return bad_input(e),
            };
            let bytes = match m.pack(&a.mesh.display().to_string()) {
                Ok(b) => b,
                Err(e) => return bad_input(e),
            };
            let r = write_atomic(&a.output, |w| {
                w.write_all(&bytes).map_err(|source| OutputError::Io {
                    path: a.output.clone(),
                    source,
                })
            });
            if let Err(e) = r {
                return bad_input(e);
            }
            out!(
                "{}: {} vertices, {} triangles, {} bytes",
                a.output.display(),
                m.positions().len(),
                m.triangles().len(),
                bytes.len()
            );
            ExitCode::SUCCESS
        }
    }
}

fn to_frame(size: u32, texels: &[texcore::color::Rgba8888]) -> Frame {
    Frame {
        width: size,
        height: size,
        pixels: texels.iter().map(|c| c.to_array()).collect(),
    }
}

/// Runs `texsim atlas`.
pub fn run_atlas(a: &AtlasArgs) -> ExitCode {
    let m = match load_mesh(&a.mesh) {
        Ok(m) => m,
        Err(e) => return bad_input(e),
    };
    if a.knobs.table_size != 256 {
        return bad_input("atlas bakes use 256-entry colour tables (--table-size 256)");
    }
    for p in [&a.output, &a.view].into_iter().flatten() {
        if let Some(parent) = p.parent().filter(|p| !p.as_os_str().is_empty()) {
            if !parent.is_dir() {
                return bad_input(format!("{}: directory does not exist", parent.display()));
            }
        }
    }
    let layout = match Layout::new(&m, a.kind, a.size, a.gutter) {
        Ok(l) => l,
        Err(e) => return bad_input(format!("{}: {e}", a.mesh)),
    };
    let material = match crate::unit::preset_material(&a.material, a.knobs.hash()) {
        Ok(x) => x,
        Err(e) => return bad_input(e),
    };
    let tex = match crate::unit::texture::<256>(&material, &a.knobs.config()) {
        Ok(t) => t,
        Err(e) => return bad_input(e),
    };
    let t0 = std::time::Instant::now();
    let baked = super::bake(&layout, &tex);
    let bake_seconds = t0.elapsed().as_secs_f64();
    if let Some(out) = &a.output {
        if let Err(e) = write_png(out, &to_frame(baked.size, &baked.texels)) {
            return bad_input(e);
        }
    }
    if let Some(view) = &a.view {
        let pyr = super::pyramid(&baked);
        let source = match (&pyr, a.sampling) {
            (Some(p), Sampling::Mip) => {
                match texcore::atlas::sample::MipAtlas::new(p, a.size as u16) {
                    Ok(mip) => Source::Mip(mip, u8::MAX),
                    Err(e) => return bad_input(e),
                }
            }
            (None, Sampling::Mip) => return bad_input("MIP sampling needs a power-of-two size"),
            _ => match texcore::atlas::sample::AtlasImage::new(
                &baked.texels,
                a.size as u16,
                a.size as u16,
            ) {
                Ok(img) => Source::Flat(img),
                Err(e) => return bad_input(e),
            },
        };
        let cam = Orbit {
            yaw: 30.0,
            pitch: 20.0,
            distance: 2.5,
            size: 256,
        };
        let f = super::view::draw(&m, &layout, &source, a.sampling, &cam);
        if let Err(e) = write_png(view, &to_frame(f.size as u32, &f.pixels)) {
            return bad_input(e);
        }
    }
    let coverage = layout.coverage();
    let scale = layout.relative_scale(&m);
    // The MIP atlas's partition: mean connected components of its sections, root down.
    let components = (a.kind == AtlasKind::Mip)
        .then(|| super::partition::Partition::new(m.triangles()).components(m.triangles()));
    if a.json {
        let j = serde_json::json!({
            "section_components": components,
            "mesh": a.mesh,
            "kind": a.kind,
            "size": a.size,
            "gutter": a.gutter,
            "triangles": m.triangles().len(),
            "coverage": coverage,
            "relative_scale": scale,
            "texels_baked": baked.written,
            "bake_seconds": bake_seconds,
        });
        out!("{j}");
    } else {
        out!(
            "{}: {:?} atlas {}x{} (gutter {}): triangles {}, coverage {:.1}%, relative_scale {:.3}, {} texels baked in {:.3} s",
            a.mesh,
            a.kind,
            a.size,
            a.size,
            a.gutter,
            m.triangles().len(),
            100.0 * coverage,
            scale,
            baked.written,
            bake_seconds
        );
        if let Some(c) = components {
            let c: Vec<String> = c.iter().map(|x| format!("{x:.2}")).collect();
            out!(
                "mean components of a section, per quadtree level: {}",
                c.join(" ")
            );
        }
    }
    ExitCode::SUCCESS
}

/// `texsim render --via-atlas N`: one frame drawn from atlases, compared with the procedural
/// frame.
pub fn render_via_atlas(
    a: &crate::cli::RenderArgs,
    host: &crate::scenes::HostScene,
    n: u32,
) -> ExitCode {
    render_atlas_frame(a, host, Some(n), &|frame, cfg, hash| {
        super::scene::render_via_atlas(host, frame, (n, a.atlas_kind), a.atlas_sampling, cfg, hash)
    })
}

/// `texsim render SCENE.toml` for a scene file with `shading = "atlas"` objects: one frame, those
/// objects from their atlases, the others procedural, compared with the all-procedural frame.
pub fn render_planned(
    a: &crate::cli::RenderArgs,
    host: &crate::scenes::HostScene,
    plan: &[Option<super::shading::AtlasShading>],
) -> ExitCode {
    render_atlas_frame(a, host, None, &|frame, cfg, hash| {
        super::scene::render_planned(host, frame, plan, cfg, hash)
    })
}

type AtlasFrameFn<'a> = dyn Fn(
        u32,
        &crate::unit::UnitConfig,
        texcore::hash::HashKind,
    ) -> Result<super::scene::AtlasRendered, String>
    + 'a;

fn render_atlas_frame(
    a: &crate::cli::RenderArgs,
    host: &crate::scenes::HostScene,
    n: Option<u32>,
    draw: &AtlasFrameFn<'_>,
) -> ExitCode {
    if a.frames.is_some() {
        return bad_input(match n {
            Some(_) => "--via-atlas draws one frame (no --frames)",
            None => "a scene with `shading = \"atlas\"` objects draws one frame (no --frames)",
        });
    }
    if let Some(parent) = a
        .output
        .as_ref()
        .and_then(|o| o.parent())
        .filter(|p| !p.as_os_str().is_empty())
    {
        if !parent.is_dir() {
            return bad_input(format!("{}: directory does not exist", parent.display()));
        }
    }
    let frame = a.frame.unwrap_or(host.scene.still());
    let cfg = a.knobs.config();
    let hash = a.knobs.hash();
    let t0 = std::time::Instant::now();
    let r = match draw(frame, &cfg, hash) {
        Ok(r) => r,
        Err(e) => return bad_input(format!("{}: {e}", a.scene)),
    };
    let seconds = t0.elapsed().as_secs_f64();
    let procedural = match crate::scenes::render_host_frame(
        host,
        frame,
        &cfg,
        hash,
        texcore::render::Output::Color,
    ) {
        Ok(p) => p,
        Err(e) => return bad_input(e),
    };
    let m = match crate::metrics::compare_rgba8(&r.frame.pixels, &procedural.frame.pixels) {
        Ok(m) => m,
        Err(e) => return bad_input(e),
    };
    if let Some(out) = &a.output {
        if let Err(e) = write_png(out, &r.frame) {
            return bad_input(e);
        }
    }
    if a.checksum && !a.json {
        out!("{:08x}", crate::scenes::checksum(&r.frame));
        return ExitCode::SUCCESS;
    }
    let via = match n {
        Some(n) => format!("via {n}x{n} atlases ({:?})", a.atlas_sampling),
        None => "with its shading = \"atlas\" objects from their atlases".to_string(),
    };
    if a.json {
        let j = serde_json::json!({
            "scene": host.scene.name,
            "frame": frame,
            "atlas_size": n,
            "sampling": a.atlas_sampling,
            "kind": n.map(|_| a.atlas_kind),
            "baked_texels": r.baked_texels,
            "bake_seconds": r.bake_seconds,
            "shaded_pixels": r.shaded,
            "psnr_vs_procedural": m.psnr,
            "within_one_step_vs_procedural": m.within_one_step,
            "checksum": crate::scenes::checksum(&r.frame),
            "seconds": seconds,
        });
        out!("{j}");
    } else {
        out!(
            "{} frame {frame} {via}: {} texels baked, {} pixels shaded; against the procedural frame PSNR {:.2} dB, {:.1}% within one step",
            host.scene.name,
            r.baked_texels,
            r.shaded,
            m.psnr,
            100.0 * m.within_one_step
        );
    }
    ExitCode::SUCCESS
}
