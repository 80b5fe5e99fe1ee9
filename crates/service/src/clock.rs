//! A scene's clock: the animation time its frames show, and how that time moves (set, played
//! at a rate, paused, looped).
//!
//! The clock lives beside the scene, on the server that takes the requests, because it reads
//! the wall clock; the scene only ever sees where the clock has got to, as ordinary `set_time`
//! edits (see [`crate::SceneSlot::follow_clock`]). Those edits go the way every edit
//! goes, under the scene's write lock and, in a cluster, to every rank: a client moving an
//! instance while the animation plays is one more edit in the same order, and a frame shows
//! the scene at one version, so at one time ([`raystage_scene::Scene::posed`]).

use std::time::{Duration, Instant};

use raystage_scene::Play;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::error::{Error, Result};
use crate::model::AnimationRef;

/// The fastest a clock may run, in scene seconds per second either way.
pub const MAX_RATE: f64 = 1000.0;

/// How often a playing clock moves the scene at most: a new time restarts every stream's
/// accumulation, so a faster tick would show fewer samples, not smoother motion, and would
/// fill a cluster's links with edits.
pub const TICK: Duration = Duration::from_millis(1000 / 60);

/// A scene's clock.
#[derive(Clone, Debug)]
pub struct Clock {
    /// The animations it plays.
    pub play: Play,
    /// Seconds from the start to the end of what it plays (the longest, for all of them).
    pub duration: f64,
    /// The time at `since`.
    base: f64,
    since: Instant,
    /// Scene seconds per wall-clock second while playing (negative plays backwards).
    pub rate: f64,
    pub playing: bool,
    /// Whether playing wraps around at the ends, or stops there.
    pub looping: bool,
    /// When the clock last moved the scene.
    pub last_tick: Option<Instant>,
}

impl Clock {
    /// A paused clock at `time` of `play`, which lasts `duration` seconds.
    pub fn paused(play: Play, duration: f64, time: f64) -> Clock {
        Clock { play, duration, base: time, since: Instant::now(), rate: 1.0, playing: false, looping: true, last_tick: None }
    }

    /// The time at `now`: where it was set, plus the rate times the time played since,
    /// wrapped around the ends (looping) or held at the end it ran into.
    pub fn time_at(&self, now: Instant) -> f64 {
        if !self.playing {
            return self.base;
        }
        let t = self.base + self.rate * now.saturating_duration_since(self.since).as_secs_f64();
        match (self.looping, self.duration > 0.0) {
            (true, true) => t.rem_euclid(self.duration),
            _ => t.clamp(0.0, self.duration),
        }
    }

    /// Whether a clock that does not loop has run into an end (and stands still there).
    fn ran_out(&self, now: Instant) -> bool {
        let t = self.time_at(now);
        self.playing && !self.looping && ((self.rate > 0.0 && t >= self.duration) || (self.rate < 0.0 && t <= 0.0))
    }

    /// Sets the time to `time` at `now`, keeping the rate and whether it plays.
    pub fn set(&mut self, time: f64, now: Instant) {
        self.base = time;
        self.since = now;
    }

    /// Stops a clock that ran into an end, there. Called before the clock is read, so that a
    /// finished animation reads as paused.
    pub fn settle(&mut self, now: Instant) {
        if self.ran_out(now) {
            self.base = self.time_at(now);
            self.playing = false;
        }
    }

    /// The clock as JSON, at `now`.
    pub fn state(&self, now: Instant) -> ClockState {
        ClockState {
            animation: self.play.into(),
            time: self.time_at(now),
            duration: self.duration,
            playing: self.playing,
            rate: self.rate,
            looping: self.looping,
        }
    }
}

/// A scene's clock (`GET /scenes/{scene}/clock`).
#[derive(Clone, Debug, PartialEq, Serialize, ToSchema)]
pub struct ClockState {
    /// The animation it plays: an index, or `all`.
    pub animation: AnimationRef,
    /// Seconds into the animation now.
    pub time: f64,
    /// Seconds the animation lasts (the longest one's, for `all`).
    pub duration: f64,
    /// Whether the time moves.
    pub playing: bool,
    /// Animation seconds per second while playing (negative plays backwards).
    pub rate: f64,
    /// Whether playing wraps around at the ends (else it stops at the end it reaches).
    #[serde(rename = "loop")]
    pub looping: bool,
}

/// A change to a scene's clock (`PUT /scenes/{scene}/clock`): fields left out stay as they are.
#[derive(Clone, Debug, Default, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ClockChange {
    /// The animation to play: its index, its name, or `all`.
    pub animation: Option<AnimationRef>,
    /// Seconds into the animation to jump to, at least 0 (past the end: the end).
    #[schema(minimum = 0)]
    pub time: Option<f64>,
    /// Plays (`true`) or pauses (`false`).
    pub playing: Option<bool>,
    /// Animation seconds per second while playing, −1000 to 1000 (negative plays backwards).
    #[schema(minimum = -1000, maximum = 1000)]
    pub rate: Option<f64>,
    /// Whether playing wraps around at the ends.
    #[serde(rename = "loop")]
    pub looping: Option<bool>,
}

impl ClockChange {
    /// Checks the numbers (the animation is checked by the edit that poses the scene).
    pub fn check(&self) -> Result<()> {
        if let Some(time) = self.time
            && !(time >= 0.0 && (time as f32).is_finite())
        {
            return Err(Error::unprocessable(Some("time".into()), format!("{time} is not a time: it must be a finite number of seconds, at least 0")));
        }
        if let Some(rate) = self.rate
            && (rate.is_nan() || rate.abs() > MAX_RATE)
        {
            return Err(Error::unprocessable(Some("rate".into()), format!("{rate} is not a rate: it must be between −{MAX_RATE} and {MAX_RATE}")));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn playing(base: f64, rate: f64, looping: bool) -> (Clock, Instant) {
        let mut clock = Clock::paused(Play::Clip(0), 2.0, base);
        let now = Instant::now();
        clock.set(base, now);
        clock.rate = rate;
        clock.looping = looping;
        clock.playing = true;
        (clock, now)
    }

    #[test]
    fn a_paused_clock_stands_still() {
        let clock = Clock::paused(Play::Clip(0), 2.0, 0.5);
        assert_eq!(clock.time_at(Instant::now() + Duration::from_secs(5)), 0.5);
    }

    #[test]
    fn a_playing_clock_moves_at_its_rate_and_wraps_when_it_loops() {
        let (clock, start) = playing(0.5, 2.0, true);
        assert!((clock.time_at(start + Duration::from_millis(250)) - 1.0).abs() < 1e-9);
        // 0.5 + 2 × 1 s = 2.5, wrapped around a 2 s animation.
        assert!((clock.time_at(start + Duration::from_secs(1)) - 0.5).abs() < 1e-9);
        let (backwards, start) = playing(0.5, -1.0, true);
        assert!((backwards.time_at(start + Duration::from_secs(1)) - 1.5).abs() < 1e-9);
    }

    #[test]
    fn a_clock_that_does_not_loop_stops_at_the_end_it_reaches() {
        let (mut clock, start) = playing(1.5, 1.0, false);
        let later = start + Duration::from_secs(3);
        assert_eq!(clock.time_at(later), 2.0);
        clock.settle(later);
        assert!(!clock.playing);
        assert_eq!(clock.time_at(later + Duration::from_secs(1)), 2.0);
        let (mut backwards, start) = playing(0.5, -1.0, false);
        backwards.settle(start + Duration::from_secs(1));
        assert!(!backwards.playing && backwards.time_at(start) == 0.0);
        // Not yet at the end: it plays on.
        let (mut clock, start) = playing(0.5, 1.0, false);
        clock.settle(start + Duration::from_millis(500));
        assert!(clock.playing);
    }

    #[test]
    fn changes_outside_the_ranges_are_refused_naming_the_field() {
        let field = |c: ClockChange| c.check().unwrap_err().detail.field;
        assert_eq!(field(ClockChange { time: Some(-1.0), ..Default::default() }), Some("time".into()));
        assert_eq!(field(ClockChange { time: Some(1e39), ..Default::default() }), Some("time".into()));
        assert_eq!(field(ClockChange { rate: Some(f64::NAN), ..Default::default() }), Some("rate".into()));
        assert_eq!(field(ClockChange { rate: Some(-1001.0), ..Default::default() }), Some("rate".into()));
        assert!(ClockChange { time: Some(0.0), rate: Some(-1000.0), ..Default::default() }.check().is_ok());
    }
}
