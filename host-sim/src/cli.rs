//! The `texsim` command line.
//!
//! Every subcommand returns an exit status: 0 on success, 1 when a check fails its bounds, 2 for
//! bad input (unknown names, malformed files, out-of-range parameters) with a message on stderr
//! naming the problem. Nothing panics on bad input, and no output file is left half written.

use std::io::Write;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use texcore::filter::{Antialias, GradientNorm, WidthSource};
use texcore::hash::HashKind;
use texcore::span::EvalMode;
use texcore::table::TableLookup;

use crate::scenes;
use crate::unit::{self, UnitConfig};

/// texsim: render, check and report on texcore textures from the host.
#[derive(Debug, Parser)]
#[command(name = "texsim", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a built-in scene or a scene file to PNG (or an animation with --frames).
    Render(RenderArgs),
    /// Render every built-in scene into a directory, one PNG each.
    Gallery(GalleryArgs),
    /// List the built-in scenes and animations, one a line, name first.
    Scenes,
    /// Compare texcore against the f64 reference on a preset's check plane or a whole scene.
    Check(CheckArgs),
    /// List the presets.
    Presets,
    /// Reports: device instruction counts (`cycles`), firmware sizes (`size`) and what each
    /// accuracy knob costs (`accuracy`).
    #[command(subcommand)]
    Report(crate::report::cli::ReportCommand),
    /// Decode a firmware's defmt stream from standard input into text lines (the device
    /// runner's decoder when `defmt-print` is not installed).
    DefmtDecode(crate::defmt_log::DefmtDecodeArgs),
    /// Mesh files: validate and pack for the device.
    #[command(subcommand)]
    Mesh(crate::atlas::cli::MeshCommand),
    /// Lay a mesh out in a texture atlas, bake a material into it, print its measures.
    Atlas(crate::atlas::cli::AtlasArgs),
}

/// What the pixels show (`--show`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ShowArg {
    /// The textures' colours.
    Color,
    /// The filter width as grey (black = 1 entry, white = the whole table).
    FilterWidth,
    /// The multipass noise stages of the scene's noise (contact sheet; needs --output).
    MultipassStages,
}

/// `texsim render`.
#[derive(Clone, Debug, Args)]
pub struct RenderArgs {
    /// Built-in scene name (see `texsim scenes`) or a scene file (.toml).
    pub scene: String,
    /// Output image: .png (an APNG when animated) or .gif (animations); `-` writes PNG/APNG to
    /// standard output. Required unless --checksum, --stats or --json asks for a printed result.
    #[arg(short, long)]
    pub output: Option<std::path::PathBuf>,
    /// Render an animation of N frames (0: the scene's own frame count; at most 1000000). Frames
    /// render in parallel on every core and stream to the encoder in order.
    #[arg(long, value_parser = crate::flags::Checked(crate::flags::frame_count))]
    pub frames: Option<u32>,
    /// Render this frame of the animation (default: the scene's still frame).
    #[arg(long, value_parser = crate::flags::Checked(crate::flags::frame_index))]
    pub frame: Option<u32>,
    /// Milliseconds per animation frame (0..=65535).
    #[arg(long, default_value_t = 80, value_parser = crate::flags::Checked(crate::flags::delay_ms))]
    pub delay: u16,
    /// Print per-stage activity counts.
    #[arg(long)]
    pub stats: bool,
    /// Print the counts (and checksum) as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Print the device checksum of the image (FNV-1a over RGB565, row-major).
    #[arg(long)]
    pub checksum: bool,
    /// What the pixels show.
    #[arg(long, value_enum, default_value_t = ShowArg::Color)]
    pub show: ShowArg,
    /// Draw every object from an N x N atlas baked once (meshed texture atlases) instead of
    /// shading it procedurally; prints the atlas frame's PSNR against the procedural one.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(8..=4096))]
    pub via_atlas: Option<u32>,
    /// Atlas look-up with --via-atlas.
    #[arg(long, value_enum, default_value_t = crate::atlas::Sampling::Bilinear)]
    pub atlas_sampling: crate::atlas::Sampling,
    /// Atlas layout with --via-atlas (as `texsim atlas --kind`).
    #[arg(long, value_enum, default_value_t = crate::atlas::AtlasKind::Uniform)]
    pub atlas_kind: crate::atlas::AtlasKind,
    /// Accuracy knobs.
    #[command(flatten)]
    pub knobs: KnobArgs,
}

/// `texsim gallery`.
#[derive(Clone, Debug, Args)]
pub struct GalleryArgs {
    /// Directory for the PNGs (created if missing).
    pub dir: std::path::PathBuf,
    /// Accuracy knobs.
    #[command(flatten)]
    pub knobs: KnobArgs,
}

/// Span evaluation mode (`--eval`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EvalArg {
    /// Per-pixel evaluation.
    Direct,
    /// Exact forward differencing (bit-identical to direct).
    Fd,
    /// Forward differencing where cells are long, direct where short (bit-identical).
    Auto,
    /// 32-bit forward differencing (bounded drift).
    Fd32,
    /// Piecewise re-anchored forward differencing of smooth-fade noise (approximate).
    Reanchored,
    /// Multipass corner-by-corner noise (see --multipass-precision, --multipass-hash).
    Multipass,
}

/// Colour-table antialiasing (`--aa`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AaArg {
    /// No filtering.
    None,
    /// Colour-table MIP map.
    Mip,
    /// Summed-area colour table.
    Csat,
    /// Three-times-long summed-area table.
    Csat3,
    /// Pre-filtered RGB565 ramp (approximate summed-area filter, one read a pixel).
    Ramp,
}

/// Where the filter widths come from (`--widths`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum WidthsArg {
    /// The analytic gradients of the texture (exact).
    Gradients,
    /// The differences of neighbouring values (approximate, cheaper: no gradients; within each triangle in scenes).
    Differences,
}

/// Gradient norm (`--norm`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormArg {
    /// Euclidean (integer square root).
    L2,
    /// Sum of absolute values.
    L1,
    /// Largest absolute value.
    Max,
}

/// Colour-table look-up (`--lookup`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LookupArg {
    /// Nearest entry.
    Nearest,
    /// Linear between entries.
    Linear,
}

/// Lattice hash (`--hash`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum HashArg {
    /// 256-entry permutation table.
    Perm,
    /// Table-free integer hash.
    Int,
}

/// The accuracy knobs shared by every rendering command.
#[derive(Clone, Debug, Args)]
pub struct KnobArgs {
    /// Span evaluation.
    #[arg(long = "eval", value_enum, default_value_t = EvalArg::Auto)]
    pub eval: EvalArg,
    /// Antialiasing filter of the colour table.
    #[arg(long, value_enum, default_value_t = AaArg::Csat)]
    pub aa: AaArg,
    /// Gradient norm of the filter width.
    #[arg(long, value_enum, default_value_t = NormArg::L2)]
    pub norm: NormArg,
    /// Where the filter widths come from.
    #[arg(long, value_enum, default_value_t = WidthsArg::Gradients)]
    pub widths: WidthsArg,
    /// Colour-table look-up.
    #[arg(long, value_enum, default_value_t = LookupArg::Nearest)]
    pub lookup: LookupArg,
    /// Colour-table entries (a power of two, 2..=1024).
    #[arg(long, default_value_t = 256, value_parser = crate::flags::Checked(crate::flags::table_size))]
    pub table_size: usize,
    /// Keep octaves past the Nyquist limit (they alias; their width still widens the filter).
    #[arg(long)]
    pub no_cull: bool,
    /// Lattice hash.
    #[arg(long, value_enum, default_value_t = HashArg::Perm)]
    pub hash: HashArg,
    /// Precision of the multipass noise passes (--eval multipass, --show multipass-stages).
    #[arg(long, value_enum, default_value_t = crate::multipass::PrecisionArg::Native)]
    pub multipass_precision: crate::multipass::PrecisionArg,
    /// Random values of the multipass noise passes.
    #[arg(long, value_enum, default_value_t = crate::multipass::HashArg::Texcore)]
    pub multipass_hash: crate::multipass::HashArg,
}

impl KnobArgs {
    /// The texture-unit configuration.
    pub fn config(&self) -> UnitConfig {
        UnitConfig {
            table_size: self.table_size,
            lookup: match self.lookup {
                LookupArg::Nearest => TableLookup::Nearest,
                LookupArg::Linear => TableLookup::Linear,
            },
            aa: match self.aa {
                AaArg::None => Antialias::None,
                AaArg::Mip => Antialias::Mip,
                AaArg::Csat => Antialias::Csat,
                AaArg::Csat3 => Antialias::Csat3,
                AaArg::Ramp => Antialias::Ramp,
            },
            norm: match self.norm {
                NormArg::L2 => GradientNorm::L2,
                NormArg::L1 => GradientNorm::L1,
                NormArg::Max => GradientNorm::Max,
            },
            mode: match self.eval {
                EvalArg::Direct => EvalMode::Direct,
                EvalArg::Fd => EvalMode::Fd,
                EvalArg::Auto => EvalMode::Auto,
                EvalArg::Fd32 => EvalMode::Fd32,
                EvalArg::Reanchored => EvalMode::Reanchored,
                EvalArg::Multipass => EvalMode::Multipass(self.multipass()),
            },
            cull: !self.no_cull,
            band_limit: texcore::bandlimit::BandLimit::DEFAULT,
            precision: texcore::model::Precision::NATIVE,
            widths: match self.widths {
                WidthsArg::Gradients => WidthSource::Gradients,
                WidthsArg::Differences => WidthSource::Differences,
            },
        }
    }

    /// The multipass setting of `--multipass-precision` and `--multipass-hash`.
    pub fn multipass(&self) -> texcore::multipass::MultipassConfig {
        texcore::multipass::MultipassConfig {
            precision: self.multipass_precision.into(),
            hash: self.multipass_hash.into(),
        }
    }

    /// The lattice hash.
    pub fn hash(&self) -> HashKind {
        match self.hash {
            HashArg::Perm => HashKind::Permutation,
            HashArg::Int => HashKind::Integer,
        }
    }
}

/// `texsim check`.
#[derive(Clone, Debug, Args)]
pub struct CheckArgs {
    /// Preset name (see `texsim presets`), built-in scene name or scene file.
    pub name: String,
    /// Check the scene of that name even when a preset has the same name (`wood`, `marble`,
    /// `fire`, `planet`, `zoneplate` are both).
    #[arg(long)]
    pub scene: bool,
    /// Animation frame of a scene (default: its still frame).
    #[arg(long, value_parser = crate::flags::Checked(crate::flags::frame_index))]
    pub frame: Option<u32>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Image size of a preset's check plane in pixels (square).
    #[arg(long, default_value_t = 256, value_parser = crate::flags::Checked(crate::flags::plane_size))]
    pub size: u32,
    /// Fail (exit 1) unless at least this fraction (0 to 1) of pixels is within one 8-bit step.
    #[arg(long, value_parser = crate::flags::Checked(crate::flags::fraction))]
    pub min_within: Option<f64>,
    /// Compare a scene with its N x N supersampled truth instead of the reference model: prints
    /// `psnr_filtered`, `psnr_unfiltered` (the same knobs with `--aa none`) and
    /// `longest_flat_band` (rows; see `host_sim::truth`).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=16))]
    pub supersampled: Option<u16>,
    /// With --supersampled: also measure the flicker around the horizon (the band of rows around
    /// the image centre) over FRAMES frames from the checked one, texcore's and the truth's.
    #[arg(long, value_name = "FRAMES", requires = "supersampled",
          value_parser = clap::value_parser!(u32).range(2..=i64::from(crate::truth::MAX_FLICKER_FRAMES)))]
    pub flicker: Option<u32>,
    /// Render a scene at this size (WIDTHxHEIGHT) instead of its own (same view).
    #[arg(long, value_name = "WxH", value_parser = parse_image_size)]
    pub image_size: Option<(u16, u16)>,
    /// Accuracy knobs.
    #[command(flatten)]
    pub knobs: KnobArgs,
}

/// Parses `WIDTHxHEIGHT` (each 1..=4096).
fn parse_image_size(s: &str) -> Result<(u16, u16), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, found `{s}`"))?;
    let side = |v: &str| -> Result<u16, String> {
        match v.trim().parse::<u16>() {
            Ok(n) if (1..=4096).contains(&n) => Ok(n),
            _ => Err(format!("image side `{v}` is not an integer in 1..=4096")),
        }
    };
    Ok((side(w)?, side(h)?))
}

/// Runs the command line; returns the process exit status.
pub fn run(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Render(a) => render(&a),
        Command::Gallery(a) => gallery(&a),
        Command::Scenes => {
            let mut out = std::io::stdout().lock();
            let all = texcore::scene::BUILTIN
                .iter()
                .chain(&texcore::scene::ANIMATIONS);
            for name in all {
                if let Some(s) = texcore::scene::by_name(name) {
                    let (w, h) = s.size();
                    let _ = writeln!(
                        out,
                        "{name}\t{w}x{h}\t{} frame{}\t{} object{}",
                        s.frames(),
                        if s.frames() == 1 { "" } else { "s" },
                        s.objects.len(),
                        if s.objects.len() == 1 { "" } else { "s" }
                    );
                }
            }
            ExitCode::SUCCESS
        }
        Command::Check(a) => check(&a),
        Command::Report(r) => crate::report::cli::run(&r),
        Command::DefmtDecode(a) => crate::defmt_log::run(&a),
        Command::Mesh(m) => crate::atlas::cli::run_mesh(&m),
        Command::Atlas(a) => crate::atlas::cli::run_atlas(&a),
        Command::Presets => {
            let mut out = std::io::stdout().lock();
            for name in texcore::presets::NAMES {
                let _ = writeln!(out, "{name}");
            }
            ExitCode::SUCCESS
        }
    }
}

/// Prints an error and returns exit status 2.
pub fn bad_input(msg: impl std::fmt::Display) -> ExitCode {
    eprintln!("texsim: error: {msg}");
    ExitCode::from(2)
}

/// A scene by built-in name or from a scene file (validated completely before anything is
/// rendered or written).
pub fn load_scene(name: &str) -> Result<scenes::HostScene, String> {
    if let Some(s) = texcore::scene::by_name(name) {
        return Ok(scenes::HostScene::builtin(s));
    }
    let path = std::path::Path::new(name);
    if path.extension().is_some_and(|e| e == "toml") || path.exists() {
        return crate::scenefile::load(path).map_err(|e| e.to_string());
    }
    Err(format!(
        "unknown scene `{name}` (built-in: {}; animations: {}; or a .toml scene file)",
        texcore::scene::BUILTIN.join(", "),
        texcore::scene::ANIMATIONS.join(", ")
    ))
}

fn render(a: &RenderArgs) -> ExitCode {
    if a.output.is_none() && !(a.checksum || a.stats || a.json) {
        return bad_input(
            "render: no output: give -o FILE (.png, or .gif for animations; - for standard \
             output), or ask for --checksum, --stats or --json",
        );
    }
    let host = match load_scene(&a.scene) {
        Ok(s) => s,
        Err(e) => return bad_input(e),
    };
    if let Some(n) = a.via_atlas {
        return crate::atlas::cli::render_via_atlas(a, &host, n);
    }
    if let Some(plan) = crate::atlas::scene::atlas_plan(&host) {
        return crate::atlas::cli::render_planned(a, &host, &plan);
    }
    let scene = &host.scene;
    let cfg = a.knobs.config();
    let hash = a.knobs.hash();
    let show = match a.show {
        ShowArg::Color => texcore::render::Output::Color,
        ShowArg::FilterWidth => texcore::render::Output::FilterWidth,
        ShowArg::MultipassStages => return crate::multipass::render_stages(a, scene, hash),
    };
    if let Some(out) = a.output.as_deref().filter(|o| !crate::output::is_stdout(o)) {
        if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
            if !parent.is_dir() {
                return bad_input(format!("{}: directory does not exist", parent.display()));
            }
        }
    }
    let (first, count) = match a.frames {
        Some(n) => (0, if n == 0 { scene.frames().max(1) } else { n }),
        None => (a.frame.unwrap_or(scene.still()), 1),
    };
    let format = match a.output.as_deref().map(crate::output::Format::of) {
        Some(Err(e)) => return bad_input(e),
        Some(Ok(f)) => Some(f),
        None => None,
    };
    let start = std::time::Instant::now();
    let frame = |i: u32| {
        scenes::render_host_frame(&host, first.wrapping_add(i), &cfg, hash, show)
            .map_err(|e| crate::output::OutputError::Frame(e.to_string()))
    };
    let last = if count == 1 {
        // A still (or a one-frame animation for .gif).
        let r = match frame(0) {
            Ok(r) => r,
            Err(e) => return bad_input(e),
        };
        let written = match (&a.output, format) {
            (Some(out), Some(crate::output::Format::Png)) => {
                crate::output::write_png(out, &r.frame)
            }
            (Some(out), Some(_)) => {
                crate::output::write_animation(out, std::slice::from_ref(&r.frame), a.delay)
            }
            _ => Ok(()),
        };
        if let Err(e) = written {
            return bad_input(e);
        }
        r
    } else {
        match animate(a, &host, count, format, frame) {
            Ok(r) => r,
            Err(crate::output::OutputError::Interrupted) => {
                eprintln!("texsim: interrupted; no file written");
                return ExitCode::from(crate::interrupt::EXIT_INTERRUPTED);
            }
            Err(e) => return bad_input(e),
        }
    };
    let elapsed = start.elapsed();
    let rendered_len = count;
    let sum = scenes::checksum(&last.frame);
    let mut out = std::io::stdout().lock();
    if a.json {
        let mut v = serde_json::to_value(scenes::StatsReport::from(&last.stats))
            .unwrap_or(serde_json::Value::Null);
        if let Some(o) = v.as_object_mut() {
            o.insert("scene".into(), scene.name.into());
            o.insert("width".into(), last.frame.width.into());
            o.insert("height".into(), last.frame.height.into());
            o.insert("frames".into(), u64::from(rendered_len).into());
            o.insert("checksum".into(), format!("{sum:08x}").into());
            o.insert(
                "host_ms".into(),
                (elapsed.as_secs_f64() * 1000.0 / f64::from(rendered_len)).into(),
            );
        }
        let _ = writeln!(out, "{v}");
    } else {
        if a.checksum {
            let _ = writeln!(out, "{sum:08x}");
        }
        if a.stats {
            let s = scenes::StatsReport::from(&last.stats);
            let _ = writeln!(
                out,
                "{}: {}x{}",
                scene.name, last.frame.width, last.frame.height
            );
            if let Ok(serde_json::Value::Object(m)) = serde_json::to_value(&s) {
                for (k, v) in m {
                    let _ = writeln!(out, "  {k:22} {v}");
                }
            }
        }
    }
    ExitCode::SUCCESS
}

/// Renders `count` frames in parallel (rayon) and streams them in order to the encoder of
/// `format` (none: rendered for the printed counts only), with a progress bar on a terminal and a
/// clean stop on Ctrl-C. Returns the last frame.
fn animate(
    a: &RenderArgs,
    host: &scenes::HostScene,
    count: u32,
    format: Option<crate::output::Format>,
    frame: impl Fn(u32) -> Result<scenes::Rendered, crate::output::OutputError> + Sync,
) -> Result<scenes::Rendered, crate::output::OutputError> {
    use crate::output::{AnimationEncoder, OutputError};
    use crate::stream::{self, Stopped};
    // Hidden when standard error is not a terminal (and with --json or `-o -`).
    let bar = if a.json || a.output.as_deref().is_some_and(crate::output::is_stdout) {
        indicatif::ProgressBar::hidden()
    } else {
        let b = indicatif::ProgressBar::new(u64::from(count));
        b.set_style(
            indicatif::ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} frames {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b.set_message(host.scene.name.to_string());
        b
    };
    let stop = crate::interrupt::flag();
    let chunk = stream::default_chunk();
    let mut last = None;
    let run = |enc: &mut dyn FnMut(&scenes::Rendered) -> Result<(), OutputError>,
               last: &mut Option<scenes::Rendered>| {
        let r = stream::ordered(count, chunk, stop, &frame, |_, r| {
            enc(&r)?;
            bar.inc(1);
            *last = Some(r);
            Ok(())
        });
        match r {
            Ok(()) => Ok(()),
            Err(Stopped::Interrupted) => Err(OutputError::Interrupted),
            Err(Stopped::Failed(e)) => Err(e),
        }
    };
    let result = match (&a.output, format) {
        (Some(out), Some(format)) => crate::output::write_dest(out, |w| {
            let mut enc: Option<AnimationEncoder<&mut dyn std::io::Write>> = None;
            let mut w = Some(w);
            run(
                &mut |r| {
                    if enc.is_none() {
                        let w = w.take().ok_or(OutputError::Interrupted)?;
                        enc = Some(AnimationEncoder::new(
                            w, out, format, &r.frame, count, a.delay,
                        )?);
                    }
                    match enc.as_mut() {
                        Some(e) => e.write_frame(&r.frame),
                        None => Err(OutputError::Interrupted),
                    }
                },
                &mut last,
            )?;
            enc.ok_or(OutputError::Interrupted)?.finish()
        }),
        _ => run(&mut |_| Ok(()), &mut last),
    };
    bar.finish_and_clear();
    result?;
    last.ok_or(OutputError::Interrupted)
}

fn gallery(a: &GalleryArgs) -> ExitCode {
    if let Err(e) = std::fs::create_dir_all(&a.dir) {
        return bad_input(format!("{}: {e}", a.dir.display()));
    }
    let cfg = a.knobs.config();
    let hash = a.knobs.hash();
    let bar = indicatif::ProgressBar::new(texcore::scene::BUILTIN.len() as u64);
    for name in texcore::scene::BUILTIN {
        bar.set_message(name);
        let Some(scene) = texcore::scene::by_name(name) else {
            continue;
        };
        let r = match scenes::render_frame(
            &scene,
            scene.still(),
            &cfg,
            hash,
            texcore::render::Output::Color,
        ) {
            Ok(r) => r,
            Err(e) => return bad_input(format!("{name}: {e}")),
        };
        if let Err(e) = crate::output::write_png(&a.dir.join(format!("{name}.png")), &r.frame) {
            return bad_input(e);
        }
        if name == "torus" {
            // Figure 9(c): the filter widths of the torus.
            let w = match scenes::render_frame(
                &scene,
                scene.still(),
                &cfg,
                hash,
                texcore::render::Output::FilterWidth,
            ) {
                Ok(r) => r,
                Err(e) => return bad_input(format!("{name}: {e}")),
            };
            if let Err(e) = crate::output::write_png(&a.dir.join("torus-widths.png"), &w.frame) {
                return bad_input(e);
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    println!(
        "{} scenes written to {}",
        texcore::scene::BUILTIN.len(),
        a.dir.display()
    );
    ExitCode::SUCCESS
}

/// `texsim check SCENE --supersampled N`.
fn check_supersampled(
    scene: &scenes::HostScene,
    frame: u32,
    cfg: &unit::UnitConfig,
    a: &CheckArgs,
    n: u16,
) -> ExitCode {
    let mut r = match crate::truth::check(scene, frame, cfg, a.knobs.hash(), n) {
        Ok(r) => r,
        Err(e) => return bad_input(e),
    };
    if let Some(frames) = a.flicker {
        match crate::truth::flicker(scene, frame, frames, cfg, a.knobs.hash(), n) {
            Ok(f) => r.flicker = Some(f),
            Err(e) => return bad_input(e),
        }
    }
    let mut out = std::io::stdout().lock();
    if a.json {
        let _ = serde_json::to_writer(&mut out, &r);
        let _ = writeln!(out);
    } else {
        let _ = writeln!(
            out,
            "{}: {}x{} pixels, frame {}, against {n}x{n} supersampled truth: filtered PSNR {:.2} dB, \
             unfiltered {:.2} dB ({:+.2} dB), longest flat band {} rows ({} flat rows; unfiltered {}); \
             on the scale: unfiltered without culling {:.2} dB, 2x2 supersampled {:.2} dB, 4x4 {:.2} dB",
            r.name,
            r.width,
            r.height,
            r.frame,
            r.psnr_filtered,
            r.psnr_unfiltered,
            r.gain_db,
            r.longest_flat_band,
            r.flat_rows,
            r.longest_flat_band_unfiltered,
            r.psnr_unfiltered_no_cull,
            r.psnr_supersampled_2x2,
            r.psnr_supersampled_4x4
        );
        if let Some(f) = &r.flicker {
            let _ = writeln!(
                out,
                "flicker over frames {}..{}, rows {}..{}: filtered {:.3}, unfiltered {:.3}, \
                 truth {:.3} (filtered / truth {:.2})",
                f.first,
                f.first.wrapping_add(f.frames),
                f.rows[0],
                f.rows[1],
                f.flicker_filtered,
                f.flicker_unfiltered,
                f.flicker_truth,
                f.ratio
            );
        }
    }
    ExitCode::SUCCESS
}

fn check(a: &CheckArgs) -> ExitCode {
    let cfg = a.knobs.config();
    let preset = if a.scene || a.supersampled.is_some() {
        Err(unit::UnitError::UnknownPreset(a.name.clone()))
    } else {
        unit::preset_material(&a.name, a.knobs.hash())
    };
    let report = match preset {
        Ok(material) => match unit::check_material(&material, &cfg, a.size) {
            Ok(r) => r,
            Err(e) => return bad_input(e),
        },
        Err(unit::UnitError::UnknownPreset(_)) => {
            let scene = match load_scene(&a.name) {
                Ok(s) => s,
                Err(e) => {
                    return bad_input(format!(
                        "{e}; presets: {}",
                        texcore::presets::NAMES.join(", ")
                    ))
                }
            };
            let mut scene = scene;
            if let Some((w, h)) = a.image_size {
                scene.scene.camera.width = w;
                scene.scene.camera.height = h;
            }
            let frame = a.frame.unwrap_or(scene.scene.still());
            if let Some(n) = a.supersampled {
                return check_supersampled(&scene, frame, &cfg, a, n);
            }
            match scenes::check_host_scene(&scene, frame, &cfg, a.knobs.hash()) {
                Ok(metrics) => {
                    let (w, h) = scene.scene.size();
                    unit::CheckReport {
                        name: scene.scene.name.to_string(),
                        width: u32::from(w),
                        height: u32::from(h),
                        config: cfg,
                        metrics,
                    }
                }
                Err(e) => return bad_input(e),
            }
        }
        Err(e) => return bad_input(e),
    };
    let mut out = std::io::stdout().lock();
    if a.json {
        let _ = serde_json::to_writer(&mut out, &report);
        let _ = writeln!(out);
    } else {
        let m = &report.metrics;
        let _ = writeln!(
            out,
            "{}: {}x{} pixels, max error {:.3}, mean error {:.4}, PSNR {:.2} dB, within one step {:.4}%",
            report.name,
            report.width,
            report.height,
            m.max_error,
            m.mean_error,
            m.psnr,
            100.0 * m.within_one_step
        );
    }
    if let Some(min) = a.min_within {
        if report.metrics.within_one_step < min {
            eprintln!(
                "texsim: check failed: within_one_step {} < {min}",
                report.metrics.within_one_step
            );
            return ExitCode::from(1);
        }
    }
    ExitCode::SUCCESS
}
