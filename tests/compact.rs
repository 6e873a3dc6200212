//! Compact vertices (20 bytes): decoded, they are the f32 mesh's vertices within the
//! documented precision, with the same indices, in every topology and with sweeps, caps
//! and points; edits rewrite them as a full write does.

// The trees of the vertex-cache figures (a10, f12, g10); its cache model is not used here.
#[allow(dead_code)]
#[path = "common/vertex_cache.rs"]
mod vertex_cache;

use arbor::Error;
use arbor::geom::Curve;
use arbor::mesh::{MeshOptions, MeshPlan, Tip, Topology, Vertex, VertexCompact, VertexFormat};
use arbor::models::honda::{self, HondaParams};
use glam::Vec3;

/// Worst normal angle (degrees), worst |du| and worst |dv| / (the mesh's v range) between
/// decoded compact vertices and the f32 ones.
fn errors(f32s: &[Vertex], compact: &[VertexCompact], v_scale: f32) -> (f64, f64, f64) {
    assert_eq!(f32s.len(), compact.len());
    let (lo, hi) = f32s.iter().fold((f32::MAX, f32::MIN), |(l, h), v| {
        (l.min(v.uv[1]), h.max(v.uv[1]))
    });
    let range = (hi - lo).max(1e-6) as f64;
    let (mut angle, mut du, mut dv) = (0.0f64, 0.0f64, 0.0f64);
    for (a, c) in f32s.iter().zip(compact) {
        let b = c.decode(v_scale);
        assert_eq!(a.position, b.position, "positions are f32 in both");
        let (na, nb) = (
            Vec3::from(a.normal).as_dvec3(),
            Vec3::from(b.normal).as_dvec3(),
        );
        if na.length() > 0.5 {
            // atan2 of |a x b| and a . b: exact for small angles, where acos of a dot
            // product rounds a length error of 1e-7 into 0.03 degrees.
            let deg = na.cross(nb).length().atan2(na.dot(nb)).to_degrees();
            angle = angle.max(deg);
        }
        du = du.max((a.uv[0] as f64 - b.uv[0] as f64).abs());
        dv = dv.max((a.uv[1] as f64 - b.uv[1] as f64).abs() / range);
    }
    (angle, du, dv)
}

fn option_sets() -> Vec<MeshOptions> {
    let mut sets = Vec::new();
    for topology in Topology::ALL {
        for (curve_rings, tip, base_cap) in [
            (0, Tip::Open, false),
            (0, Tip::Cap, true),
            (2, Tip::Point, true),
        ] {
            sets.push(
                MeshOptions::default()
                    .topology(topology)
                    .curve_rings(curve_rings)
                    .tip(tip)
                    .base_cap(base_cap),
            );
        }
    }
    sets
}

#[test]
fn decoded_compact_meshes_match_the_f32_meshes() {
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for (name, s) in vertex_cache::trees() {
        for o in option_sets() {
            let f = MeshPlan::new(&s, &o).unwrap().mesh(&s).unwrap();
            let oc = o.vertex_format(VertexFormat::Compact);
            let plan = MeshPlan::new(&s, &oc).unwrap();
            assert_eq!(plan.size(), MeshPlan::new(&s, &o).unwrap().size());
            let size = plan.size();
            let mut v = vec![VertexCompact::default(); size.vertices];
            let mut idx = vec![0u32; size.indices];
            plan.write(&s, &mut v, &mut idx).unwrap();
            assert_eq!(idx, f.indices, "{name} {o:?}: indices");
            // What docs/meshes.md says: no v below 0 (which the format clamps) here.
            assert!(f.vertices.iter().all(|v| v.uv[1] >= 0.0), "{name}: v < 0");
            let v_scale = plan.v_scale();
            let v_max = f.vertices.iter().fold(0.0f32, |m, v| m.max(v.uv[1]));
            assert!(
                v_scale >= v_max && v_scale < 2.0 * v_max.max(1.0),
                "{name}: v_scale {v_scale} for v up to {v_max}"
            );
            let e = errors(&f.vertices, &v, v_scale);
            assert!(e.0 <= 0.1, "{name} {o:?}: normal {}°", e.0);
            assert!(e.1 <= 1.0 / 4096.0, "{name} {o:?}: u {}", e.1);
            assert!(e.2 <= 1.0 / 4096.0, "{name} {o:?}: v {} of the range", e.2);
            worst = (worst.0.max(e.0), worst.1.max(e.1), worst.2.max(e.2));
        }
    }
    // The figures docs/meshes.md states.
    assert!(worst.0 < 0.01, "worst normal error {}°", worst.0);
    assert!(
        worst.1 <= 1.0 / 131070.0 + 1e-9,
        "worst u error {}",
        worst.1
    );
    assert!(
        worst.2 <= 1.0 / 65535.0,
        "worst v error {} of the range",
        worst.2
    );
    println!(
        "worst: normal {}°, u {}, v {} of the range",
        worst.0, worst.1, worst.2
    );
}

#[test]
fn a_write_into_the_other_format_names_vertex_format() {
    let s = honda::build(&HondaParams::preset('a').unwrap()).unwrap();
    let compact = MeshOptions::default().vertex_format(VertexFormat::Compact);
    let plan = MeshPlan::new(&s, &compact).unwrap();
    let size = plan.size();
    let mut v = vec![Vertex::default(); size.vertices];
    let mut idx = vec![0u32; size.indices];
    let e = plan.write(&s, &mut v, &mut idx).unwrap_err();
    assert!(matches!(e, Error::InvalidArgument { .. }), "{e}");
    assert!(e.to_string().contains("vertex_format"), "{e}");
    assert!(
        arbor::mesh::tubes(&s, &compact).is_err(),
        "an owned mesh is f32"
    );
    let plan = MeshPlan::new(&s, &MeshOptions::default()).unwrap();
    let mut c = vec![VertexCompact::default(); size.vertices];
    let e = plan.write(&s, &mut c, &mut idx).unwrap_err();
    assert!(e.to_string().contains("vertex_format"), "{e}");
    assert_eq!(plan.v_scale(), 1.0, "f32 vertices are written as they are");
}

#[test]
fn edits_rewrite_compact_vertices_as_a_full_write_does() {
    let base = honda::build(&HondaParams::preset('a').unwrap()).unwrap();
    let o = MeshOptions::default().vertex_format(VertexFormat::Compact);
    // A twig bent in place, and the trunk stretched far enough to need a larger v_scale.
    for (i, stretch) in [(base.len() - 1, 1.0f32), (0, 600.0)] {
        let mut s = base.clone();
        let mut plan = MeshPlan::new(&s, &o).unwrap();
        let size = plan.size();
        let mut v = vec![VertexCompact::default(); size.vertices];
        let mut idx = vec![0u32; size.indices];
        plan.write(&s, &mut v, &mut idx).unwrap();
        let before = plan.v_scale();
        let c = s.curve(i);
        let curve = Curve {
            p1: c.p0 + (c.p1 - c.p0) * stretch + Vec3::new(0.01, 0.0, 0.0),
            p2: c.p0 + (c.p2 - c.p0) * stretch,
            p3: c.p0 + (c.p3 - c.p0) * stretch,
            ..c
        };
        let b = s.branches()[i];
        s.set_curve(i, &curve, b.start_radius, b.end_radius)
            .unwrap();
        let changed = plan.update_after_edit(&s, i).unwrap();
        plan.rewrite(&s, &changed, &mut v).unwrap();
        let fresh = MeshPlan::new(&s, &o).unwrap();
        assert_eq!(plan.v_scale(), fresh.v_scale());
        let mut w = vec![VertexCompact::default(); size.vertices];
        fresh.write(&s, &mut w, &mut idx).unwrap();
        assert_eq!(
            bytemuck::cast_slice::<VertexCompact, u8>(&v),
            bytemuck::cast_slice::<VertexCompact, u8>(&w),
            "branch {i} stretched {stretch}"
        );
        if stretch > 1.0 {
            assert!(
                plan.v_scale() > before,
                "the stretch needs a larger v_scale"
            );
            assert_eq!(changed.len(), s.len(), "so every vertex is rewritten");
        } else {
            assert!(changed.len() <= 2);
        }
    }
}

#[test]
fn the_packed_animation_stream_decodes_to_the_f32_one() {
    for (name, s) in vertex_cache::trees() {
        let plan = MeshPlan::new(&s, &MeshOptions::default()).unwrap();
        let full = plan.animation(&s).unwrap();
        let packed = plan.animation_compact(&s).unwrap();
        assert_eq!(full.len(), packed.len());
        assert_eq!(full.len(), plan.size().vertices, "one element per vertex");
        for (a, p) in full.iter().zip(&packed) {
            let d = p.decode();
            assert_eq!(d.order, a.order, "{name}: order is exact");
            for (x, y) in [(d.growth, a.growth), (d.along, a.along), (d.phase, a.phase)] {
                assert!((x - y).abs() <= 0.5 / 65535.0 + 1e-7, "{name}: {x} vs {y}");
            }
        }
    }
}
