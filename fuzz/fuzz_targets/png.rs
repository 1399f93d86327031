//! Images for the 2D system: the header's size is judged first (as `load_image` does, here
//! against 64 k pixels to keep executions fast), then decoded and split into bodies. Nothing may
//! panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use rigidref::blocks2d::image::{ImageSettings, blocks_from_pixels};

fuzz_target!(|data: &[u8]| {
    let reader = || image::ImageReader::new(std::io::Cursor::new(data)).with_guessed_format();
    let Ok(r) = reader() else { return };
    let Ok((w, h)) = r.into_dimensions() else { return };
    if u64::from(w) * u64::from(h) > 65_536 {
        return;
    }
    let Ok(r) = reader() else { return };
    let Ok(img) = r.decode() else { return };
    let img = img.to_rgba8();
    let pixels: Vec<[u8; 4]> = img.pixels().map(|p| p.0).collect();
    let _ = blocks_from_pixels(img.width() as usize, img.height() as usize, &pixels, &ImageSettings::default());
});
