//! Writes the material comparison scenes as glTF (see `raystage_demo::material_scenes`) into
//! the folder given, as `NAME.gltf`, for renderers other than raystage to read:
//! `scripts/references/materials.py` renders them with Mitsuba 3 (those it translates:
//! `MaterialScene::MITSUBA`; write them alone with `--mitsuba`), and
//! `scripts/references/cycles_gltf.py` with Blender's Cycles.

use raystage_demo::material_scenes::MaterialScene;

fn main() -> std::io::Result<()> {
    let args: Vec<_> = std::env::args_os().skip(1).collect();
    let mitsuba = args.iter().any(|a| a == "--mitsuba");
    let Some(folder) = args.iter().find(|a| *a != "--mitsuba") else {
        eprintln!("usage: write_material_scenes [--mitsuba] FOLDER");
        std::process::exit(2);
    };
    let folder = std::path::PathBuf::from(folder);
    std::fs::create_dir_all(&folder)?;
    let scenes: &[MaterialScene] = if mitsuba { &MaterialScene::MITSUBA } else { &MaterialScene::ALL };
    for scene in scenes {
        std::fs::write(folder.join(format!("{}.gltf", scene.name())), scene.gltf())?;
    }
    Ok(())
}
