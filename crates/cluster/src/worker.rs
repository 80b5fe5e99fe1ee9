//! A render worker: every rank but 0 of `raystage serve --mpi` runs [`work`] until rank 0
//! says stop.

use std::collections::{HashMap, VecDeque};
use std::sync::Arc;
use std::time::Instant;

use raystage_render::{Progressive, Share};
use raystage_scene::Scene;

use raystage_service::{AppState, Blob, Config, Edit, Error};

use crate::Transport;
use crate::wire::{Message, PassMessage, Reply, decode, encode};

/// Versions of each scene a worker keeps: a pass names the version rank 0 took its snapshot
/// of, and edits made meanwhile may have reached the worker first. More than a few edits
/// between a frame's snapshot and its turn is unlikely; a pass that finds its version gone is
/// rendered by rank 0 alone.
const VERSIONS_KEPT: usize = 8;

/// Serves rank 0 of the job `transport` reaches until it says stop: applies its edits to
/// replicas of its scenes (checked against the same `config` limits), renders this rank's share
/// of its passes. `scenes` are the scenes every rank built before (from the command line), by
/// id. `Err` if rank 0 cannot be heard (the job is ending).
pub fn work(transport: &dyn Transport, config: Config, scenes: Vec<(u32, Scene, String)>) -> Result<(), String> {
    let mut worker = Worker { transport, state: AppState::new(config), versions: HashMap::new(), accumulations: HashMap::new() };
    for (id, scene, origin) in scenes {
        worker.state.insert_scene(id, scene, origin).map_err(|e| e.detail.message)?;
        worker.keep_version(id);
    }
    loop {
        match decode::<Message<Edit>>(&worker.next()?)? {
            Message::Stop => return Ok(()),
            Message::NewScene { id, origin, build } => {
                let result = build.build(&worker.state.config().limits).and_then(|(scene, _)| worker.state.insert_scene(id, scene, origin));
                let inserted = result.is_ok();
                if worker.voted(result.map(|_| ()).map_err(|e| e.detail.message))? {
                    worker.keep_version(id);
                } else if inserted {
                    let _ = worker.state.forget_scene(id);
                }
            }
            Message::DeleteScene { id } => {
                let result = worker.state.forget_scene(id);
                worker.versions.remove(&id);
                worker.voted(result.map_err(|e| e.detail.message))?;
            }
            Message::Edit { scene, edit } => {
                let limits = worker.state.config().limits;
                let slot = match worker.state.scene(scene) {
                    Ok(slot) => slot,
                    Err(e) => {
                        worker.voted(Err(e.detail.message))?;
                        continue;
                    }
                };
                let mut vote_failed = None;
                let result = slot.edit_blocking(edit, &limits, |local| match worker.voted(local) {
                    Ok(true) => Ok(()),
                    Ok(false) => Err(Error::internal("another rank refused the edit")),
                    Err(e) => {
                        vote_failed = Some(e);
                        Err(Error::internal("rank 0 cannot be heard"))
                    }
                });
                if let Some(e) = vote_failed {
                    return Err(e);
                }
                if result.is_ok() {
                    worker.keep_version(scene);
                }
            }
            Message::Verdict { .. } => return Err("a verdict came with no edit before it".into()),
            Message::Pass(pass) => {
                let reply = worker.render(pass);
                worker.transport.send(0, &encode(&reply), None)?;
            }
        }
    }
}

struct Worker<'a> {
    transport: &'a dyn Transport,
    state: AppState,
    /// The last versions of each scene, newest last.
    versions: HashMap<u32, VecDeque<(u64, Arc<Scene>)>>,
    /// This rank's share of each accumulation in progress, by key.
    accumulations: HashMap<u64, Progressive>,
}

impl Worker<'_> {
    /// The next message from rank 0.
    fn next(&self) -> Result<Vec<u8>, String> {
        self.transport.receive(0, None)?.ok_or_else(|| "rank 0 sent nothing".to_string())
    }

    /// Answers rank 0 with how applying went here and waits for its verdict: whether the edit
    /// stands. `Err` if rank 0 cannot be heard.
    fn voted(&self, local: Result<(), String>) -> Result<bool, String> {
        let reply = match local {
            Ok(()) => Reply::Applied,
            Err(why) => Reply::Refused(why),
        };
        self.transport.send(0, &encode(&reply), None)?;
        match decode::<Message<Edit>>(&self.next()?)? {
            Message::Verdict { stands } => Ok(stands),
            _ => Err("rank 0 sent another message where a verdict was due".into()),
        }
    }

    /// Keeps scene `id` as it is now among its versions.
    fn keep_version(&mut self, id: u32) {
        let Ok(slot) = self.state.scene(id) else { return };
        let versions = self.versions.entry(id).or_default();
        versions.push_back(slot.snapshot_blocking());
        while versions.len() > VERSIONS_KEPT {
            versions.pop_front();
        }
    }

    /// Renders this rank's share of a pass.
    fn render(&mut self, pass: PassMessage) -> Reply {
        for key in &pass.ended {
            self.accumulations.remove(key);
        }
        let Some(scene) = self.versions.get(&pass.scene).and_then(|v| v.iter().find(|(version, _)| *version == pass.version)).map(|(_, s)| Arc::clone(s)) else {
            return Reply::Failed(format!("scene {} at version {} is not held here", pass.scene, pass.version));
        };
        let settings = pass.settings;
        let share = Share { index: self.transport.rank(), count: self.transport.ranks() };
        if pass.reset {
            self.accumulations.remove(&pass.key);
        } else if !self.accumulations.contains_key(&pass.key) {
            return Reply::Failed(format!("accumulation {} is not held here", pass.key));
        }
        let progressive = match self.accumulations.entry(pass.key) {
            std::collections::hash_map::Entry::Occupied(entry) => entry.into_mut(),
            std::collections::hash_map::Entry::Vacant(entry) => match Progressive::new(settings).and_then(|p| p.with_share(share)) {
                Ok(progressive) => entry.insert(progressive),
                Err(e) => return Reply::Failed(e.to_string()),
            },
        };
        let start = Instant::now();
        let stats = progressive.add(&scene.frame(), pass.samples);
        let seconds = start.elapsed().as_secs_f64();
        let pixels = progressive.film().share_values(share).iter().flat_map(|v| v.to_le_bytes()).collect();
        let reply = Reply::Share {
            pixels: Blob(pixels),
            counts: stats.share_counts(),
            seconds,
        };
        if pass.last {
            self.accumulations.remove(&pass.key);
        }
        reply
    }
}
