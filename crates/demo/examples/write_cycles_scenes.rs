//! Writes the scenes Blender's Cycles is the reference for into the folder given, as
//! `NAME.gltf`: the Cornell box with rough dielectric walls (`cornell_box.gltf`, see
//! `raystage_demo::cornell_box::rough_dielectric_gltf`), `MaterialScene::CYCLES`, and the
//! animated assets wrapped with their cameras (`NAME.glb`, `AnimatedAsset::ALL`).
//! `scripts/references/cycles_gltf.py` renders them; `tests/cycles_reference.rs` compares.

use raystage_demo::animated_assets::AnimatedAsset;
use raystage_demo::material_scenes::MaterialScene;

fn main() -> std::io::Result<()> {
    let Some(folder) = std::env::args_os().nth(1) else {
        eprintln!("usage: write_cycles_scenes FOLDER");
        std::process::exit(2);
    };
    let folder = std::path::PathBuf::from(folder);
    std::fs::create_dir_all(&folder)?;
    std::fs::write(folder.join("cornell_box.gltf"), raystage_demo::cornell_box::rough_dielectric_gltf())?;
    for scene in MaterialScene::CYCLES {
        std::fs::write(folder.join(format!("{}.gltf", scene.name())), scene.gltf())?;
    }
    for asset in AnimatedAsset::ALL {
        std::fs::write(folder.join(format!("{}.glb", asset.name())), asset.glb())?;
    }
    Ok(())
}
