//! Playing a glTF file's animations from the command line: `render --time` poses the scene
//! before its frame, `render --frames` renders a sequence of frames from one import (the scene
//! is reused: each frame poses it again, and the next frame refits or rebuilds what moved).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail, ensure};
use raystage_render::OutputFormat;
use raystage_scene::{AnimationChoice, Play, Scene};

use crate::render::{RenderJob, RenderReport, SceneSource, prepare, render_with_progress, settings_for};

/// A moment of a glTF file's animations, as `render --time` and `--animation` give it.
#[derive(Clone, Debug, PartialEq)]
pub struct ScenePose {
    /// Seconds from the animation's start (before its first keyframe it holds its first
    /// values, after its last its last).
    pub time: f32,
    /// The animation: its name, its index, or `all` for every one together; `None` for the
    /// first.
    pub animation: Option<String>,
    /// Seconds the shutter stays open from `time` (and from each frame's time of a sequence):
    /// the instances the animation moves blur along their motion over that interval, where the
    /// integrator simulates motion blur (distribution, path); `None` for an instant.
    pub shutter: Option<f32>,
}

/// Frames `first..=last` of a file's animation at `fps` frames per second: frame `n` shows
/// time `n / fps`. Each is written to the output path with its number in place of the
/// pattern's `%d` or `%0Nd` (`frame_%04d.png` → `frame_0012.png`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sequence {
    /// The first frame.
    pub first: u32,
    /// The last frame (included).
    pub last: u32,
    /// Frames per second.
    pub fps: f32,
}

/// Parses `--frames FIRST..LAST` (both included).
pub fn parse_frames(text: &str) -> Result<(u32, u32)> {
    let parsed = text.split_once("..").and_then(|(a, b)| Some((a.trim().parse::<u32>().ok()?, b.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((first, last)) if first <= last => Ok((first, last)),
        _ => bail!("`{text}` is not FIRST..LAST, two frame numbers with the first not after the last"),
    }
}

/// Which animations `choice` names in `scene` (see [`Play::choose`]): a number is an index,
/// other text a name or `all`; the first for none.
fn play_for(scene: &Scene, choice: Option<&str>) -> Result<Play> {
    let animations = scene.animations();
    let named = choice.map(|text| text.parse().map_or(AnimationChoice::Name(text), AnimationChoice::Index));
    let Some(play) = Play::choose(&animations, named) else {
        let names: Vec<String> = animations
            .iter()
            .enumerate()
            .map(|(k, a)| if a.name.is_empty() { format!("{k} (unnamed, {:.3} s)", a.duration) } else { format!("{k} `{}` ({:.3} s)", a.name, a.duration) })
            .collect();
        bail!("no animation `{}`: the file has {} (or `all`)", choice.unwrap_or_default(), names.join(", "))
    };
    Ok(play)
}

/// Poses `scene` as `pose` says; a file without animations is left as it is, with a note.
pub(crate) fn pose(scene: &mut Scene, pose: &ScenePose, log: &mut impl Write, name: &str) -> Result<()> {
    ensure!(pose.time.is_finite(), "--time must be a number of seconds, got {}", pose.time);
    if scene.animations().is_empty() {
        writeln!(log, "note: {name}: has no animations: --time and --animation change nothing")?;
        return Ok(());
    }
    let play = play_for(scene, pose.animation.as_deref())?;
    pose_at(scene, play, pose.time, pose.shutter, name)?;
    writeln!(log, "{name}: posed at {:.3} s of {}", pose.time, describe(scene, play))?;
    Ok(())
}

/// Poses `scene` at `time` seconds of `play`, its instances moving over `shutter` seconds from
/// then with the camera's shutter open over the interval, if given.
fn pose_at(scene: &mut Scene, play: Play, time: f32, shutter: Option<f32>, name: &str) -> Result<()> {
    let Some(open) = shutter else {
        return scene.pose(play, time).with_context(|| format!("cannot pose {name} at {time} s"));
    };
    ensure!(open.is_finite() && open > 0.0, "--shutter must be a positive number of seconds, got {open}");
    scene.pose_over(play, time, time + open).with_context(|| format!("cannot pose {name} from {time} s to {} s", time + open))?;
    let camera = raystage_scene::Camera { shutter: [0.0, 1.0], ..*scene.camera() };
    scene.set_camera(camera).context("cannot open the camera's shutter")?;
    Ok(())
}

/// What `play` plays, for the log: an animation with its index, name and length, or all.
fn describe(scene: &Scene, play: Play) -> String {
    let animations = scene.animations();
    match play {
        Play::Clip(k) if animations[k].name.is_empty() => format!("animation {k} ({:.3} s long)", animations[k].duration),
        Play::Clip(k) => format!("animation {k} `{}` ({:.3} s long)", animations[k].name, animations[k].duration),
        Play::All => format!("all {} animations", animations.len()),
    }
}

/// The path of frame `n`: the pattern's `%d` or `%0Nd` replaced by the number.
fn frame_path(pattern: &Path, n: u32) -> Result<PathBuf> {
    let text = pattern.to_string_lossy();
    let Some(start) = text.find('%') else { bail!("--out must hold %d or %0Nd (frame_%04d.png) to number the frames of --frames") };
    let rest = &text[start + 1..];
    let digits = rest.find('d').filter(|&end| rest[..end].chars().all(|c| c.is_ascii_digit()));
    let Some(end) = digits else { bail!("--out: `%` must start %d or %0Nd, in {text}") };
    let width: usize = rest[..end].parse().unwrap_or(0);
    Ok(PathBuf::from(format!("{}{n:0width$}{}", &text[..start], &rest[end + 1..])))
}

/// Renders `sequence` of the job's glTF file: one import, posed and rendered once per frame,
/// each frame written as it is done, then the time per frame spent posing (animation
/// evaluation, skinning and morphing), updating trees (lazy builds, refits and rebuilds, timed
/// inside the render) and rendering.
pub(crate) fn render_sequence(job: &RenderJob, sequence: &Sequence, log: &mut impl Write) -> Result<RenderReport> {
    let SceneSource::File { pose: chosen, .. } = &job.scene else { bail!("--frames plays a glTF file's animation; a demo has --frame") };
    ensure!(sequence.fps.is_finite() && sequence.fps > 0.0, "--fps must be a positive number, got {}", sequence.fps);
    ensure!(job.channels.is_empty(), "--channels is for one frame, not --frames");
    let (given, pool) = prepare(job)?;
    let format = OutputFormat::from_path(&job.out)?;
    frame_path(&job.out, sequence.first)?;
    let setup = Instant::now();
    let mut scene = job.scene.load(log, &job.environment, given.render.default_lights)?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    ensure!(!scene.animations().is_empty(), "{} has no animations to render frames of", job.scene.name());
    let play = play_for(&scene, chosen.as_ref().and_then(|p| p.animation.as_deref()))?;
    let settings = settings_for(&given, &job.settings, &scene);
    writeln!(log, "{}: {} frames of {} at {} frames per second", job.scene.name(), sequence.last - sequence.first + 1, describe(&scene, play), sequence.fps)?;
    let (mut posing, mut updates, mut rendering) = (0.0, 0.0, 0.0);
    let mut last = None;
    for n in sequence.first..=sequence.last {
        let time = n as f32 / sequence.fps;
        let start = Instant::now();
        pose_at(&mut scene, play, time, chosen.as_ref().and_then(|p| p.shutter), &job.scene.name())?;
        let posed = start.elapsed().as_secs_f64();
        let (film, frame, _) = pool.install(|| render_with_progress(&scene, &settings, raystage_render::Share::WHOLE)).context("bad render settings")?;
        let path = frame_path(&job.out, n)?;
        std::fs::write(&path, film.encode(format, given.look).context("cannot encode the image")?).with_context(|| format!("cannot write {}", path.display()))?;
        writeln!(log, "frame {n} at {time:.3} s: pose {posed:.3} s, trees {:.3} s, render {:.3} s -> {}", frame.work.build_seconds, frame.seconds - frame.work.build_seconds, path.display())?;
        posing += posed;
        updates += frame.work.build_seconds;
        rendering += frame.seconds - frame.work.build_seconds;
        last = Some(frame);
    }
    let count = f64::from(sequence.last - sequence.first + 1);
    writeln!(
        log,
        "{} frames of {} at {}x{} {} {} spp, per frame: pose {:.3} s, tree updates {:.3} s, render {:.3} s",
        count,
        job.scene.name(),
        settings.width,
        settings.height,
        settings.integrator.name(),
        settings.samples_per_pixel,
        posing / count,
        updates / count,
        rendering / count
    )?;
    let triangles = scene.object_ids().map(|id| scene.mesh(id).map_or(0, |m| m.indices.len())).sum();
    Ok(RenderReport { triangles, threads: pool.current_num_threads(), frame: last.expect("a sequence has a frame"), setup_seconds })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_patterns_number_the_frames() {
        assert_eq!(frame_path(Path::new("out/frame_%04d.png"), 12).unwrap(), PathBuf::from("out/frame_0012.png"));
        assert_eq!(frame_path(Path::new("f%d.png"), 3).unwrap(), PathBuf::from("f3.png"));
        assert!(frame_path(Path::new("frame.png"), 3).is_err());
        assert!(frame_path(Path::new("frame_%s.png"), 3).is_err());
        assert_eq!(parse_frames("0..24").unwrap(), (0, 24));
        assert!(parse_frames("5..2").is_err() && parse_frames("5").is_err());
    }
}
