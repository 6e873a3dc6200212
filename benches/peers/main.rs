//! Derivation speed of arbor beside symbios and dcc-lsystem (see run.sh).
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

/// Seconds (median of 7) and the module count of the last run.
fn time<F: FnMut() -> usize>(mut f: F) -> (f64, usize) {
    let mut n = 0;
    let samples = (0..7)
        .map(|_| {
            let t = Instant::now();
            n = f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    (median(samples), n)
}

fn arbor_derive(text: &str, steps: u32) -> usize {
    let ls = arbor::lsystem::LSystem::parse(text).unwrap();
    let o = arbor::lsystem::LsystemOptions::default().steps(Some(steps)).max_modules(usize::MAX).max_params(usize::MAX);
    ls.derive(&o).unwrap().len()
}

fn symbios(rule: &str, axiom: &str, steps: usize) -> usize {
    let mut sys = symbios::System::new();
    sys.max_capacity = 200_000_000;
    sys.state.max_capacity = 200_000_000;
    sys.add_rule(rule).unwrap();
    sys.set_axiom(axiom).unwrap();
    sys.derive(steps).unwrap();
    sys.state.len()
}

fn dcc(steps: usize) -> usize {
    let mut b = dcc_lsystem::LSystemBuilder::new();
    let f = b.token("F");
    let plus = b.token("+");
    let minus = b.token("-");
    let open = b.token("[");
    let close = b.token("]");
    b.axiom(vec![f]);
    b.transformation_rule(
        f,
        vec![f, open, plus, f, close, f, open, minus, f, close, f],
    );
    let mut s = b.finish();
    s.step_by(steps);
    s.get_state().len()
}

fn row(name: &str, arbor: (f64, usize), peers: &[(&str, (f64, usize))]) {
    let rate = |(t, n): (f64, usize)| n as f64 / t / 1e6;
    print!("| {name} | {} | {:.1} |", arbor.1, rate(arbor));
    for (peer, r) in peers {
        assert_eq!(r.1, arbor.1, "{peer} made a different number of modules");
        print!(
            " {peer}: {:.1} ({:.1}×) |",
            rate(*r),
            rate(arbor) / rate(*r)
        );
    }
    println!();
}

/// arbor's bark triangles per second from parameters (build + mesh, triangle list): 6
/// sides at the three.js generator's sizes (about 6,000 and 48,000 triangles), 8 sides
/// around ez-tree's and larger.
fn mesh_rows() {
    for (name, steps, sides) in [
        ('a', 9u32, 6u32),
        ('a', 12, 6),
        ('a', 10, 8),
        ('a', 14, 8),
        ('f', 15, 8),
    ] {
        let mut p = arbor::models::honda::HondaParams::preset(name).unwrap();
        p.steps = steps;
        let o = arbor::mesh::MeshOptions::default().radial_segments(sides);
        let mut tris = 0;
        let mut verts = 0;
        let (t, _) = time(|| {
            let s = arbor::models::honda::build(&p).unwrap();
            let m = arbor::mesh::tubes(&s, &o).unwrap();
            tris = m.indices.len() / 3;
            verts = m.vertices.len();
            tris
        });
        println!(
            "| arbor tree {name}, n = {steps}, {sides} sides | {tris} | {verts} (u32 indices) | {:.2} |",
            tris as f64 / t / 1e6
        );
    }
}

fn main() {
    if std::env::args().nth(1).as_deref() == Some("mesh") {
        mesh_rows();
        return;
    }
    let fig = "Axiom: F\nF --> F[+F]F[-F]F\n";
    let honda_g = "#define r 0.8\n#define w 0.7071\n\
                   Axiom: A(100,30)\n\
                   A(s,u) : s >= 0 --> !(u)F(s)[+(30)/(137)A(s*r,u*w)][+(-30)/(137)A(s*r,u*w)]\n";
    let symbios_g =
        "A(s,w) : s >= 0 -> !(w)F(s)[+(30)/(137)A(s*0.8,w*0.7071)][+(-30)/(137)A(s*0.8,w*0.7071)]";
    println!("| work | modules | arbor M modules/s | peers M modules/s (arbor's ratio) |");
    println!("|---|---|---|---|");
    for n in [7u32, 8] {
        let a = time(|| arbor_derive(fig, n));
        let s = time(|| symbios("F -> F[+F]F[-F]F", "F", n as usize));
        let d = time(|| dcc(n as usize));
        row(
            &format!("ABOP 1.24a, n = {n}"),
            a,
            &[("symbios", s), ("dcc-lsystem", d)],
        );
    }
    let a = time(|| arbor_derive(honda_g, 18));
    let s = time(|| symbios(symbios_g, "A(100,30)", 18));
    row("1996 tree g, n = 18 (parametric)", a, &[("symbios", s)]);
}
