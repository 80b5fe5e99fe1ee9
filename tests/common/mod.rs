//! Helpers shared by the command-line tests: temporary paths and a glTF file written in code
//! (no binary assets in the repository).

#![allow(dead_code, reason = "each test file uses some of the helpers")]

use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicU32, Ordering};

/// A fresh path in Cargo's temporary directory for integration tests, unique to this process.
pub fn temp(name: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_file(&path);
    path
}

/// `mpirun` as the MPI tests start it: allowed to run as root (the tests do, in CI), more ranks
/// than cores, and a directory of its own for Open MPI's session files (`TMPDIR`): jobs that
/// parallel tests start at the same moment raced to create the shared one, and the loser's
/// job never started ("mkdir /tmp/ompi.vm.0: File exists"). Short, under the system's
/// temporary directory: the session directory holds sockets, whose paths are limited.
pub fn mpirun() -> Command {
    static JOBS: AtomicU32 = AtomicU32::new(0);
    let dir = std::env::temp_dir().join(format!("raystage-mpi-{}-{}", std::process::id(), JOBS.fetch_add(1, Ordering::Relaxed)));
    std::fs::create_dir_all(&dir).expect("a session directory for mpirun");
    let mut command = Command::new("mpirun");
    command.env("OMPI_ALLOW_RUN_AS_ROOT", "1").env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1").env("TMPDIR", dir).arg("--oversubscribe");
    command
}

/// A triangle with an unlit green material, its buffer in a `.bin` file beside the `.gltf`.
pub fn write_gltf() -> PathBuf {
    let mut buffer = Vec::new();
    for p in [[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]] {
        p.iter().for_each(|c| buffer.extend(c.to_le_bytes()));
    }
    let bin = temp("triangle.bin");
    std::fs::write(&bin, &buffer).unwrap();
    let document = format!(
        r#"{{
            "asset": {{ "version": "2.0" }},
            "extensionsUsed": ["KHR_materials_unlit"],
            "buffers": [{{ "byteLength": 36, "uri": "{}" }}],
            "bufferViews": [{{ "buffer": 0, "byteLength": 36 }}],
            "accessors": [{{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0] }}],
            "materials": [{{ "pbrMetallicRoughness": {{ "baseColorFactor": [0, 1, 0, 1] }}, "extensions": {{ "KHR_materials_unlit": {{}} }} }}],
            "meshes": [{{ "primitives": [{{ "attributes": {{ "POSITION": 0 }}, "material": 0 }}] }}],
            "nodes": [{{ "mesh": 0 }}],
            "scenes": [{{ "nodes": [0] }}]
        }}"#,
        bin.file_name().unwrap().to_str().unwrap()
    );
    let path = temp("triangle.gltf");
    std::fs::write(&path, document).unwrap();
    path
}

