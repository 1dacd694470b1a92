//! Recording the window to an animated GIF (the G key): frames are read back from the screen,
//! shrunk, and encoded on a worker thread so the window keeps its frame rate; the file is
//! written whole when recording stops.

use kea_render::{GifWriter, Image};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Time between recorded frames: 25 frames a second, played back at the same speed.
pub const FRAME_INTERVAL: Duration = Duration::from_millis(40);
/// Most frames one recording keeps (30 s); recording stops by itself there.
pub const MAX_FRAMES: u32 = 750;
/// Recorded frames are shrunk to at most this width, pixels.
pub const MAX_WIDTH: u32 = 520;

/// A recording under way.
pub struct Recorder {
    path: PathBuf,
    size: (u32, u32),
    frames: u32,
    last: Option<Instant>,
    sender: Option<Sender<Image>>,
    worker: Option<JoinHandle<Result<Vec<u8>, String>>>,
}

impl Recorder {
    /// Starts a recording of `width` × `height` frames (already shrunk) into `path`.
    pub fn start(path: &Path, width: u32, height: u32) -> Result<Self, String> {
        let delay = (FRAME_INTERVAL.as_millis() / 10) as u16;
        let mut gif = GifWriter::new(width, height, delay)?;
        let (sender, frames) = channel::<Image>();
        let worker = std::thread::spawn(move || {
            for image in frames {
                gif.push(&image)?;
            }
            gif.finish()
        });
        Ok(Self {
            path: path.to_path_buf(),
            size: (width, height),
            frames: 0,
            last: None,
            sender: Some(sender),
            worker: Some(worker),
        })
    }

    /// Whether the next frame is due (and the recording has room for it).
    #[must_use]
    pub fn due(&self) -> bool {
        self.frames < MAX_FRAMES && self.last.is_none_or(|t| t.elapsed() >= FRAME_INTERVAL)
    }

    /// Whether the recording is full.
    #[must_use]
    pub fn is_full(&self) -> bool {
        self.frames >= MAX_FRAMES
    }

    /// Frames recorded so far.
    #[must_use]
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// The size frames must have.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Adds a frame; one of another size (the window was resized) is left out.
    pub fn push(&mut self, image: Image) {
        if (image.width, image.height) != self.size || self.is_full() {
            return;
        }
        if let Some(s) = &self.sender {
            if s.send(image).is_ok() {
                self.frames += 1;
                self.last = Some(Instant::now());
            }
        }
    }

    /// Stops, waits for the encoder and writes the file; returns the path and frame count.
    pub fn finish(mut self) -> Result<(PathBuf, u32), String> {
        drop(self.sender.take());
        let bytes = self
            .worker
            .take()
            .ok_or("the recording was already finished")?
            .join()
            .map_err(|_| "the GIF encoder stopped unexpectedly".to_string())??;
        if self.frames == 0 {
            return Err("no frames were recorded".into());
        }
        kea_render::write_file(&self.path, &bytes)?;
        Ok((self.path.clone(), self.frames))
    }
}

/// The size a `width` × `height` window is recorded at, and the whole factor it is shrunk by.
#[must_use]
pub fn recorded_size(width: u32, height: u32) -> (u32, u32, u32) {
    let factor = width.div_ceil(MAX_WIDTH).max(1);
    ((width / factor).max(1), (height / factor).max(1), factor)
}

/// `image` shrunk by a whole `factor`, each pixel the mean of a `factor` × `factor` block.
#[must_use]
pub fn shrink(image: &Image, factor: u32) -> Image {
    let factor = factor.max(1);
    let (w, h) = (
        (image.width / factor).max(1),
        (image.height / factor).max(1),
    );
    let mut pixels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0u32; 3];
            let mut n = 0;
            for dy in 0..factor {
                for dx in 0..factor {
                    let (sx, sy) = (x * factor + dx, y * factor + dy);
                    if sx < image.width && sy < image.height {
                        let p = image.pixel(sx, sy);
                        for (s, c) in sum.iter_mut().zip(p) {
                            *s += u32::from(c);
                        }
                        n += 1;
                    }
                }
            }
            let n = n.max(1);
            pixels.push(sum.map(|s| (s / n) as u8));
        }
    }
    Image {
        width: w,
        height: h,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shrinking_averages_blocks() {
        let image = Image {
            width: 4,
            height: 2,
            pixels: vec![
                [0, 0, 0],
                [100, 100, 100],
                [10, 20, 30],
                [10, 20, 30],
                [200, 200, 200],
                [100, 100, 100],
                [10, 20, 30],
                [10, 20, 30],
            ],
        };
        let small = shrink(&image, 2);
        assert_eq!((small.width, small.height), (2, 1));
        assert_eq!(small.pixels, vec![[100, 100, 100], [10, 20, 30]]);
        assert_eq!(recorded_size(1024, 720,), (512, 360, 2));
        assert_eq!(recorded_size(400, 300), (400, 300, 1));
    }

    #[test]
    fn a_recording_writes_a_gif_with_its_frames() {
        let path = std::env::temp_dir().join(format!("kea-record-{}.gif", std::process::id()));
        let mut r = Recorder::start(&path, 8, 6).unwrap();
        for k in 0..3u8 {
            r.push(Image {
                width: 8,
                height: 6,
                pixels: vec![[k * 80, 10, 200]; 48],
            });
        }
        // A frame of another size is left out.
        r.push(Image {
            width: 4,
            height: 6,
            pixels: vec![[0, 0, 0]; 24],
        });
        assert_eq!(r.frames(), 3);
        let (written, frames) = r.finish().unwrap();
        assert_eq!((written.as_path(), frames), (path.as_path(), 3));
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.starts_with(b"GIF89a"), "a GIF");
        let _ = std::fs::remove_file(&path);
        let empty = Recorder::start(&path, 8, 6).unwrap();
        assert!(empty.finish().unwrap_err().contains("no frames"));
        assert!(!path.exists(), "nothing is written without frames");
    }
}
