//! Rows handed out while a frame renders (`render_rows`): every row exactly once, final, and
//! encoded exactly as the finished film encodes it.

use std::sync::Mutex;

use raystage_render::{Integrator, RenderSettings, render_rows};

#[test]
fn finished_rows_are_the_films_rows() {
    let scene = raystage_demo::shading::cornell_room().unwrap();
    for (integrator, spp) in [(Integrator::EyeLight, 1), (Integrator::Path, 3)] {
        let settings = RenderSettings { width: 37, height: 45, integrator, samples_per_pixel: spp, ..RenderSettings::default() };
        let bands = Mutex::new(Vec::new());
        let (film, _) = render_rows(&scene.frame(), &settings, None, |rows| bands.lock().unwrap().push((rows.rows(), rows.rgb8()))).unwrap();
        let mut bands = bands.into_inner().unwrap();
        bands.sort_by_key(|(rows, _)| rows.start);
        let mut next = 0;
        for (rows, bytes) in &bands {
            assert_eq!(rows.start, next, "{integrator:?}: every row once, in bands that tile the image");
            assert_eq!(*bytes, film.rgb8_rows(rows.clone(), raystage_render::Look::default()), "{integrator:?}: rows {rows:?}");
            next = rows.end;
        }
        assert_eq!(next, 45);
    }
}
