//! Writes the classic Cornell box as glTF (see `raystage_demo::cornell_box`) to the path given,
//! for renderers other than raystage to read: `scripts/references/cornell_box.py` renders it
//! with Mitsuba 3.

fn main() -> std::io::Result<()> {
    let Some(path) = std::env::args_os().nth(1) else {
        eprintln!("usage: write_cornell_box OUT.gltf");
        std::process::exit(2);
    };
    std::fs::write(path, raystage_demo::cornell_box::gltf())
}
