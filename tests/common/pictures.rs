//! Pictures from the example programs (the gallery, the ray marcher): each built against
//! the static library of this test run and rendered headless under `xvfb-run` with Mesa's
//! software OpenGL, read back as PPM and checked pixel by pixel.

use super::{lib_dir, run};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Fails with the install line unless GLFW, libpng and xvfb are there.
pub fn require_gl_tools() {
    let ok = Command::new("pkg-config")
        .args(["--exists", "glfw3", "libpng"])
        .status()
        .is_ok_and(|s| s.success())
        && Command::new("xvfb-run").arg("--help").output().is_ok();
    if !ok {
        super::missing("GLFW, libpng or xvfb");
    }
}

/// Builds `examples/NAME/NAME.c` into the test run's scratch folder (once per test binary
/// and program: two tests building one path at once would run a file another is still
/// writing, "Text file busy").
pub fn build(name: &'static str) -> PathBuf {
    static BUILT: std::sync::Mutex<Vec<(&'static str, PathBuf)>> =
        std::sync::Mutex::new(Vec::new());
    let mut built = BUILT.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, exe)) = built.iter().find(|(n, _)| *n == name) {
        return exe.clone();
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    // What an example's Makefile generates before its C compiles: the gallery embeds the
    // reference impostor shader (examples/common/impostor.glsl) as a string.
    if name == "gallery" {
        run(Command::new("make")
            .args(["-s", "-C"])
            .arg(root.join("examples/gallery"))
            .arg("impostor_glsl.h"));
    }
    let flags = run(Command::new("pkg-config").args(["--cflags", "--libs", "glfw3", "libpng"]));
    run(Command::new("cc")
        .args(["-std=c11", "-O1", "-Wall", "-Wextra", "-Werror", "-I"])
        .arg(root.join("include"))
        .arg(root.join(format!("examples/{name}/{name}.c")))
        .arg(lib_dir().join("libarbor.a"))
        .args(flags.split_whitespace())
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe));
    built.push((name, exe.clone()));
    exe
}

pub struct Image {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<u8>,
}

impl Image {
    pub fn pixel(&self, x: usize, y: usize) -> (i32, i32, i32) {
        let i = 3 * (y * self.width + x);
        (
            self.rgb[i] as i32,
            self.rgb[i + 1] as i32,
            self.rgb[i + 2] as i32,
        )
    }

    pub fn tree(&self, x: usize, y: usize) -> bool {
        let (r, g, b) = self.pixel(x, y);
        // Bark is brown: red above green above blue. Sky is blue, the ground green.
        r > b + 12 && r >= g
    }

    /// The organ colour of the L-system mode: pink (red well above green and blue).
    pub fn organ(&self, x: usize, y: usize) -> bool {
        let (r, g, b) = self.pixel(x, y);
        r > g + 40 && r > b + 20
    }

    pub fn count(&self, f: impl Fn(&Self, usize, usize) -> bool) -> usize {
        (0..self.height)
            .flat_map(|y| (0..self.width).map(move |x| (x, y)))
            .filter(|&(x, y)| f(self, x, y))
            .count()
    }

    pub fn share(&self, x0: usize, y0: usize, w: usize, h: usize) -> f64 {
        let mut n = 0;
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                n += self.tree(x, y) as usize;
            }
        }
        n as f64 / (w * h) as f64
    }
}

/// How many pixels differ between two pictures of one size.
pub fn differing_pixels(a: &Image, b: &Image) -> usize {
    a.rgb
        .chunks_exact(3)
        .zip(b.rgb.chunks_exact(3))
        .filter(|(p, q)| p != q)
        .count()
}

/// Runs `exe` with `args` under xvfb-run, rendering into a PPM, and reads it back; returns
/// the picture and the program's output.
pub fn render_with_output(exe: &Path, name: &str, args: &[&str]) -> (Image, String) {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}.ppm"));
    let output = run(Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x1024x24"])
        .arg(exe)
        .arg("--screenshot")
        .arg(&path)
        .args(["--frames", "2"])
        .args(args));
    let data = std::fs::read(&path).unwrap();
    let header: Vec<&[u8]> = data.splitn(4, |&c| c == b'\n').take(3).collect();
    assert_eq!(header[0], b"P6");
    let dims = String::from_utf8_lossy(header[1]).into_owned();
    let mut dims = dims.split_whitespace().map(|v| v.parse::<usize>().unwrap());
    let (width, height) = (dims.next().unwrap(), dims.next().unwrap());
    let offset = header.iter().map(|h| h.len() + 1).sum::<usize>();
    let rgb = data[offset..].to_vec();
    assert_eq!(rgb.len(), width * height * 3);
    (Image { width, height, rgb }, output)
}

/// [`render_with_output`], the picture only.
pub fn render(exe: &Path, name: &str, args: &[&str]) -> Image {
    render_with_output(exe, name, args).0
}
