//! Writes the classic Cornell box as glTF (see `raystage_demo::cornell_box`) to the path given,
//! for renderers other than raystage to read: `scripts/references/cornell_box.py` renders it
//! with Mitsuba 3. With `--spheres`, the room with a million triangles of spheres on its floor
//! instead of the blocks.
//!
//! ```sh
//! cargo run -p raystage-demo --example write_cornell_box -- room.gltf
//! cargo run -p raystage-demo --example write_cornell_box -- --spheres spheres.gltf
//! ```

fn main() -> std::io::Result<()> {
    let mut args: Vec<_> = std::env::args_os().skip(1).collect();
    let spheres = args.first().is_some_and(|a| a == "--spheres");
    if spheres {
        args.remove(0);
    }
    let [path] = args.as_slice() else {
        eprintln!("usage: write_cornell_box [--spheres] OUT.gltf");
        std::process::exit(2);
    };
    let gltf = if spheres { raystage_demo::cornell_box::spheres_gltf() } else { raystage_demo::cornell_box::gltf() };
    std::fs::write(path, gltf)
}
