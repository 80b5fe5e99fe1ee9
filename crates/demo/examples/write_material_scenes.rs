//! Writes the material comparison scenes as glTF (see `raystage_demo::material_scenes`) into
//! the folder given, as `NAME.gltf`, for renderers other than raystage to read:
//! `scripts/references/materials.py` renders them with Mitsuba 3.

use raystage_demo::material_scenes::MaterialScene;

fn main() -> std::io::Result<()> {
    let Some(folder) = std::env::args_os().nth(1) else {
        eprintln!("usage: write_material_scenes FOLDER");
        std::process::exit(2);
    };
    let folder = std::path::PathBuf::from(folder);
    std::fs::create_dir_all(&folder)?;
    for scene in MaterialScene::ALL {
        std::fs::write(folder.join(format!("{}.gltf", scene.name())), scene.gltf())?;
    }
    Ok(())
}
