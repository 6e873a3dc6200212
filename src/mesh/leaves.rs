//! Leaves: where they go (the turtle's `~` sites, the tips of outer branches), as instance
//! data for instanced drawing or baked into a leaf mesh (quads, a prefab from an OBJ file,
//! and the turtle's `{ . }` polygons triangulated).

use super::animation::{AnimationVertex, branch_phase, growth_times};
use super::check_options;
use super::plan::kept_branches;
use super::rings::AxisMap;
use super::rings::Slot;
use super::strips::{StripRules, StripWriter, zigzag};
use super::{Mesh, MeshOptions, MeshSize, RESTART_INDEX, Vertex};
use crate::error::{Error, Result};
use crate::geom::transport::ring_basis;
use crate::geom::unit;
use crate::rng::Rng;
use crate::skeleton::Skeleton;
use glam::{Mat3, Quat, Vec3};
use std::mem::MaybeUninit;
use std::path::Path;

/// The atlas cell (0..columns × rows, row by row) of leaf `k` (the order of
/// [`leaf_instances`] with [`keep`](LeafOptions::keep) 1; [`leaf_cells`] for a thinned
/// crown's) with these options: the cell whose rectangle
/// ([`LeafAtlas::rect`](crate::texture::LeafAtlas::rect)) the baked leaf `k` samples, and
/// an instanced one should.
pub fn leaf_cell(leaves: &LeafOptions, k: usize) -> u32 {
    cell_of(leaves.seed, leaves.atlas_columns * leaves.atlas_rows, k)
}

/// The branch each of [`leaf_instances`] sits on ([`NO_PARENT`](crate::skeleton::NO_PARENT)
/// for a site the turtle recorded on none), in the order of the baked leaf mesh's leaves.
pub fn leaf_branches(
    skeleton: &Skeleton,
    leaves: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<Vec<u32>> {
    Ok(place_kept(skeleton, leaves, mesh)?
        .into_iter()
        .map(|(_, b, _)| b)
        .collect())
}

/// The atlas cell of each of [`leaf_instances`] (the cell [`leaf_cell`] gives its index
/// among all the leaves, so a thinned leaf keeps its cell).
pub fn leaf_cells(
    skeleton: &Skeleton,
    leaves: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<Vec<u32>> {
    Ok(place_kept(skeleton, leaves, mesh)?
        .into_iter()
        .map(|(_, _, k)| leaf_cell(leaves, k))
        .collect())
}

/// The [`keep`](LeafOptions::keep) that keeps `m` of `n` leaves (at least one): 1 when
/// `m >= n`.
pub fn keep_for(n: usize, m: usize) -> f32 {
    if m >= n {
        return 1.0;
    }
    (m.max(1) as f32 / n as f32).max(1e-6)
}

fn keep_rank(seed: u64, k: usize) -> f32 {
    let r = crate::rng::Rng::new(!seed ^ (k as u64).wrapping_mul(0xd1b5_4a32_d192_ed03)).next_u64();
    (r >> 40) as f32 / (1u64 << 24) as f32
}

fn cell_of(seed: u64, cells: u32, k: usize) -> u32 {
    if cells > 1 {
        (crate::rng::Rng::new(seed ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)).next_u64()
            % cells as u64) as u32
    } else {
        0
    }
}

/// One leaf for instanced drawing (glDrawElementsInstanced), 32 bytes; C: ArborLeafInstance.
///
/// The leaf's own space has +Y along the blade (stem to tip), +Z its face normal and +X
/// across; `rotation` (a unit quaternion x, y, z, w) turns that space into the tree's, then
/// `scale` and `position` apply. The output conventions of the mesh options (up axis,
/// uniform scale) are applied too.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LeafInstance {
    /// Where the leaf's stem attaches.
    pub position: [f32; 3],
    /// Unit quaternion (x, y, z, w) from leaf space to model space.
    pub rotation: [f32; 4],
    /// Uniform scale of the leaf shape.
    pub scale: f32,
}

const _: () = assert!(std::mem::size_of::<LeafInstance>() == 32);

/// A leaf shape for baked leaf meshes: triangles in leaf space (+Y along the blade, +Z the
/// face), for example a cluster of grass blades loaded from an OBJ file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LeafPrefab {
    /// Vertices in leaf space.
    pub vertices: Vec<Vertex>,
    /// Triangles, counter-clockwise seen from the front.
    pub triangles: Vec<[u32; 3]>,
}

impl LeafPrefab {
    /// The default leaf: a quad 0.5 wide and 1 long, its stem at the origin.
    pub fn quad() -> Self {
        let v = |x: f32, y: f32, u: f32, w: f32| Vertex {
            position: [x, y, 0.0],
            normal: [0.0, 0.0, 1.0],
            uv: [u, w],
        };
        LeafPrefab {
            vertices: vec![
                v(-0.25, 0.0, 0.0, 0.0),
                v(0.25, 0.0, 1.0, 0.0),
                v(0.25, 1.0, 1.0, 1.0),
                v(-0.25, 1.0, 0.0, 1.0),
            ],
            triangles: vec![[0, 1, 3], [3, 1, 2]],
        }
    }

    /// [`quad`](Self::quad) folded along its midrib by `degrees` (each half turned up
    /// toward +Z by half of it, a V seen from the tip): six vertices, four triangles, the
    /// same uv.
    pub fn folded(degrees: f32) -> Self {
        let half = (0.5 * degrees.clamp(0.0, 180.0)).to_radians();
        let (c, s) = (half.cos(), half.sin());
        // The halves' outer edges rise by 0.25 sin(half); each half's normal leans
        // inward, away from its edge.
        let v = |side: f32, y: f32, u: f32, w: f32| {
            let x = 0.25 * side * c;
            let n = if side == 0.0 {
                [0.0, 0.0, 1.0]
            } else {
                [-side * s, 0.0, c]
            };
            Vertex {
                position: [x, y, 0.25 * side.abs() * s],
                normal: n,
                uv: [u, w],
            }
        };
        LeafPrefab {
            vertices: vec![
                v(-1.0, 0.0, 0.0, 0.0),
                v(0.0, 0.0, 0.5, 0.0),
                v(1.0, 0.0, 1.0, 0.0),
                v(-1.0, 1.0, 0.0, 1.0),
                v(0.0, 1.0, 0.5, 1.0),
                v(1.0, 1.0, 1.0, 1.0),
            ],
            triangles: vec![[0, 1, 3], [3, 1, 4], [1, 2, 4], [4, 2, 5]],
        }
    }

    /// Loads every model of an OBJ file (triangulated; normals computed flat-per-vertex
    /// where the file has none; uv (0, 0) where it has none), as a regular file of at
    /// most [`DEFAULT_MAX_FILE_BYTES`](crate::files::DEFAULT_MAX_FILE_BYTES); its
    /// materials (`mtllib`) are not read.
    pub fn from_obj(path: impl AsRef<Path>) -> Result<Self> {
        Self::from_obj_with(path, &crate::files::FileOptions::default())
    }

    /// [`from_obj`](Self::from_obj) under a file policy and byte budget: the host names
    /// the file, so every policy reads it ([`FileAccess::Host`](crate::files::FileAccess::Host)
    /// through the host's reader), and only a regular file of at most `files.max_bytes`.
    pub fn from_obj_with(
        path: impl AsRef<Path>,
        files: &crate::files::FileOptions,
    ) -> Result<Self> {
        let path = path.as_ref();
        let loaded = crate::files::Loader::new(files, None).read_named(path, "leaf prefab")?;
        let mut reader = std::io::BufReader::new(loaded.bytes.as_slice());
        let (models, _) = tobj::load_obj_buf(&mut reader, &tobj::GPU_LOAD_OPTIONS, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| {
            Error::Io(std::io::Error::other(format!(
                "cannot load leaf prefab {}: {e}",
                path.display()
            )))
        })?;
        let mut prefab = LeafPrefab::default();
        for model in models {
            let m = &model.mesh;
            let base = prefab.vertices.len() as u32;
            let n = m.positions.len() / 3;
            for i in 0..n {
                let p = [
                    m.positions[3 * i],
                    m.positions[3 * i + 1],
                    m.positions[3 * i + 2],
                ];
                let normal = if m.normals.len() >= 3 * n {
                    [m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]]
                } else {
                    [0.0, 0.0, 1.0]
                };
                let uv = if m.texcoords.len() >= 2 * n {
                    [m.texcoords[2 * i], m.texcoords[2 * i + 1]]
                } else {
                    [0.0, 0.0]
                };
                prefab.vertices.push(Vertex {
                    position: p,
                    normal,
                    uv,
                });
            }
            for t in m.indices.chunks_exact(3) {
                prefab
                    .triangles
                    .push([base + t[0], base + t[1], base + t[2]]);
            }
        }
        prefab.validate(&path.display().to_string())?;
        Ok(prefab)
    }

    fn validate(&self, what: &str) -> Result<()> {
        let n = self.vertices.len() as u32;
        if self.triangles.is_empty() {
            return Err(Error::invalid("prefab", format!("{what} has no triangles")));
        }
        if let Some(t) = self.triangles.iter().find(|t| t.iter().any(|&i| i >= n)) {
            return Err(Error::invalid(
                "prefab",
                format!("{what}: triangle {t:?} indexes past {n} vertices"),
            ));
        }
        let finite = self.vertices.iter().all(|v| {
            v.position
                .iter()
                .chain(&v.normal)
                .chain(&v.uv)
                .all(|x| x.is_finite())
        });
        if !finite {
            return Err(Error::invalid(
                "prefab",
                format!("{what} has a non-finite value"),
            ));
        }
        Ok(())
    }
}

crate::options::options! {
/// Where leaves go and how they vary. `Default` gives the documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct LeafOptions {
    /// A leaf at every `~` site the turtle recorded. Default true.
    pub sites: bool = true,
    /// The turtle's `{ . }` polygons in the baked leaf mesh. Default true.
    pub polygons: bool = true,
    /// Leaves at the tips of terminal branches (those no branch grows from). Default false.
    pub tips: bool = false,
    /// Only tips of branches born at this rewriting step or later get leaves, so leaves
    /// sit on the young twigs. Default 0.
    pub min_birth: u32 = 0,
    /// Expected leaves per tip: the whole part always, the fraction by chance. Finite,
    /// 0..=64. Default 1.
    pub density: f32 = 1.0, checked In(0.0, 64.0), "0..=64 leaves per tip",
    /// Leaf size in model units (the prefab is scaled by it). Finite, > 0. Default 1.
    pub size: f32 = 1.0, checked Above(0.0), "a finite number > 0",
    /// Each leaf's size varies by up to ± this fraction, in [0, 1). Default 0.2.
    pub size_jitter: f32 = 0.2, checked InBelow(0.0, 1.0), "0 <= size_jitter < 1",
    /// Each leaf turns about its stem by up to ± this many degrees. Finite. Default 180.
    pub rotation_jitter: f32 = 180.0, checked Any, "a finite angle",
    /// How far tip leaves lean out from the branch, degrees. Finite. Default 30.
    pub tilt: f32 = 30.0, checked Any, "a finite angle",
    /// Seed of the variation. Default 0.
    pub seed: u64 = 0,
    /// The baked shape, loaded once and shared by every call that uses it; `None` is
    /// [`LeafPrefab::quad`].
    pub prefab: Option<std::sync::Arc<LeafPrefab>> = None,
    /// Placing more leaves than this fails with
    /// [`Error::LimitExceeded`](crate::error::Error::LimitExceeded) naming `max_leaves`, before
    /// their memory is spent. Default [`DEFAULT_MAX_LEAVES`](crate::limits::DEFAULT_MAX_LEAVES).
    pub max_leaves: usize = crate::limits::DEFAULT_MAX_LEAVES,
    /// Columns of the leaf atlas the baked leaves sample, 1..=16: each baked leaf maps
    /// its prefab's uv (0..=1) into one cell of a grid of `atlas_columns` by `atlas_rows`
    /// cells (as a leaf atlas lays out its variants), the cell chosen by the leaf's index
    /// and `seed`. Default 1 (the prefab's uv as it is).
    pub atlas_columns: u32 = 1, checked In(1, 16), "1..=16 cells",
    /// Rows of the leaf atlas, 1..=16. Default 1.
    pub atlas_rows: u32 = 1, checked In(1, 16), "1..=16 cells",
    /// Leaves whose shape reaches into the wood of a branch thicker than this radius
    /// (model units) are left out: the shape's vertices (a prefab of more than 16: the
    /// corners of its bounding box) and its centre are tested against every such
    /// branch's cone. 0 (the default) keeps every leaf.
    pub wood_clearance: f32 = 0.0, checked AtLeast(0.0), "a finite radius >= 0",
    /// The default card folded along its midrib by this angle, degrees (0..=90): each
    /// half turns up toward the face by half of it, a V seen from the tip. Baked leaves
    /// only (a prefab is used as it is; an instanced leaf is the host's shape). Default 0.
    pub fold: f32 = 0.0, checked In(0.0, 90.0), "0..=90 degrees",
    /// Each leaf turned about its own axis (heading) so its face looks as near to the light
    /// (+Y, up in model space) as it can, before `rotation_jitter`, which then varies it
    /// by up to that many degrees either way. Default false (turned at random).
    pub face_light: bool = false,
    /// The fraction of leaves kept, in (0, 1], for levels of detail: the outermost leaves
    /// of the crown (nearest its edge in their direction from its centre) stay as they
    /// are, 85% of those kept; the rest are drawn from the inside by a rank from `seed`
    /// and each leaf's index, enlarged about their middles so the inside keeps its leaf
    /// area. The leaves kept at a smaller `keep` are nearly all among
    /// those kept at a larger one, where they were (their middles), on the same atlas
    /// cells ([`leaf_cells`]): the same leaves from level to level. Default 1 (every leaf).
    pub keep: f32 = 1.0, checked AboveTo(0.0, 1.0), "0 < keep <= 1",
    /// How much a thinned crown's inside leaves are enlarged (see `keep`): each by the
    /// inside's leaves over those kept there, to this power, 0..=1. 0.5 (the default)
    /// keeps the inside's leaf area; less leaves the inside sparser, more makes it
    /// fuller. A chain of levels of detail also tries four fifths of it for each level
    /// and keeps whichever holds the silhouette better (a weeping or narrow crown seen
    /// small shows its inside through gaps that area-keeping leaves close).
    pub keep_enlarge: f32 = 0.5, checked In(0.0, 1.0), "0..=1",
}
}

impl LeafOptions {
    /// The shape each baked leaf is: the prefab, else the quad (folded by `fold`).
    pub fn shape(&self) -> std::sync::Arc<LeafPrefab> {
        self.prefab.clone().unwrap_or_else(|| {
            std::sync::Arc::new(if self.fold > 0.0 {
                LeafPrefab::folded(self.fold)
            } else {
                LeafPrefab::quad()
            })
        })
    }

    /// Refuses options out of their documented ranges (density, sizes, jitters, tilt,
    /// `max_leaves`, a prefab's data), naming the first.
    pub fn validate(&self) -> Result<()> {
        self.check_fields()?;
        if let Some(p) = &self.prefab {
            p.validate("the prefab")?;
        }
        Ok(())
    }
}

/// Leaves in model space, before output conventions, with the branch each sits on; only
/// on branches the mesh of `mesh` keeps (see [`MeshOptions::cull_radius`]).
fn place(skeleton: &Skeleton, o: &LeafOptions, mesh: &MeshOptions) -> Result<Vec<LeafInstance>> {
    Ok(place_kept(skeleton, o, mesh)?
        .into_iter()
        .map(|(l, _, _)| l)
        .collect())
}

fn place_on(
    skeleton: &Skeleton,
    o: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<Vec<(LeafInstance, u32)>> {
    // The same validation as the bark's, then the leaf's own, including the products
    // that size every leaf (so no leaf can overflow to a non-finite number).
    check_options(mesh)?;
    o.validate()?;
    check_sizes(skeleton, o, mesh)?;
    let kept = kept_branches(skeleton, mesh.cull_radius);
    let mut placer = Placer {
        o,
        rng: Rng::new(o.seed),
        out: Vec::new(),
    };
    if o.sites {
        for site in skeleton.leaves() {
            if site.branch != crate::skeleton::NO_PARENT && !kept[site.branch as usize] {
                continue;
            }
            let (p, h, u) = (site.position, site.heading, site.up);
            placer.leaf(
                site.branch,
                Vec3::from(p),
                Vec3::from(h),
                Vec3::from(u),
                0.0,
            )?;
        }
    }
    if o.tips {
        let branches = skeleton.branches();
        let adjacency = skeleton.adjacency();
        let whole = o.density.floor() as u32;
        let frac = o.density - whole as f32;
        for (i, b) in branches.iter().enumerate() {
            // A tip is a kept branch with no kept child: where the mesh's tubes end.
            let inner = adjacency.children(i).iter().any(|&c| kept[c as usize]);
            if inner || !kept[i] || b.birth < o.min_birth {
                continue;
            }
            let count = whole + u32::from((placer.rng.next_f64() as f32) < frac);
            let heading = b.end() - b.start();
            let up = ring_basis(heading.as_dvec3().normalize_or(glam::DVec3::Y))
                .0
                .as_vec3();
            for _ in 0..count {
                placer.leaf(i as u32, b.end(), heading, up, -o.tilt)?;
            }
        }
    }
    let mut out = placer.out;
    if o.wood_clearance > 0.0 {
        let points = leaf_points(&o.shape());
        let wood = Wood::new(skeleton, o.wood_clearance);
        out.retain(|(l, _)| !wood.holds(l, &points));
    }
    Ok(out)
}

/// [`place_on`] thinned by `keep`: the leaves that stay, enlarged, each with its branch
/// and its index among all the leaves (which picks its atlas cell).
fn place_kept(
    skeleton: &Skeleton,
    o: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<Vec<(LeafInstance, u32, usize)>> {
    thin(&place_on(skeleton, o, mesh)?, o)
}

/// Every leaf a crown's options place (before [`keep`](LeafOptions::keep) thins them),
/// kept to make several thinnings of one crown ([`leaf_mesh_placed`]: a chain of levels of
/// detail) without placing and testing every leaf against the wood again.
#[derive(Clone, Debug)]
pub struct Placed {
    leaves: Vec<(LeafInstance, u32)>,
    options: LeafOptions,
    mesh: MeshOptions,
}

impl Placed {
    /// How many leaves were placed.
    pub fn len(&self) -> usize {
        self.leaves.len()
    }

    /// Whether none was.
    pub fn is_empty(&self) -> bool {
        self.leaves.is_empty()
    }
}

/// The leaves of `skeleton` as `leaves` (whatever its `keep`) places them with `mesh`.
pub fn place_all(skeleton: &Skeleton, leaves: &LeafOptions, mesh: &MeshOptions) -> Result<Placed> {
    let options = leaves.clone().keep(1.0);
    Ok(Placed {
        leaves: place_on(skeleton, &options, mesh)?,
        options,
        mesh: *mesh,
    })
}

/// [`leaf_mesh`] from leaves placed once: the same mesh, thinned by `leaves.keep`. Placed
/// with other options (besides `keep` and `keep_enlarge`) or another mesh's, they are placed
/// again.
pub fn leaf_mesh_placed(
    skeleton: &Skeleton,
    placed: &Placed,
    leaves: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<Mesh> {
    // Placing does not depend on how a thinned crown is kept (`keep`, `keep_enlarge`).
    let placing = leaves
        .clone()
        .keep(1.0)
        .keep_enlarge(placed.options.keep_enlarge);
    if placed.mesh != *mesh || placed.options != placing {
        return leaf_mesh(skeleton, leaves, mesh);
    }
    let plan = leaf_plan_from(skeleton, thin(&placed.leaves, leaves)?, leaves, mesh)?;
    baked(skeleton, mesh, &plan)
}

/// `all` (placed) thinned by `o.keep`: copies of the leaves that stay.
fn thin(all: &[(LeafInstance, u32)], o: &LeafOptions) -> Result<Vec<(LeafInstance, u32, usize)>> {
    let middle = leaf_points(&o.shape())
        .last()
        .copied()
        .unwrap_or(Vec3::ZERO);
    let n = all.len();
    if o.keep >= 1.0 || n == 0 {
        return Ok(all
            .iter()
            .enumerate()
            .map(|(k, &(l, b))| (l, b, k))
            .collect());
    }
    let m = ((o.keep as f64 * n as f64 + 1e-3).floor() as usize).clamp(1, n);
    let shell_count = ((SHELL_SHARE * m as f32).round() as usize).min(m);
    let outer = outerness(all, middle);
    // The shell: the outermost leaves, as they are.
    let mut by_outer: Vec<usize> = (0..n).collect();
    by_outer.sort_by(|&a, &b| outer[b].total_cmp(&outer[a]).then(a.cmp(&b)));
    let mut kept = vec![false; n];
    let mut in_shell = vec![false; n];
    for &k in &by_outer[..shell_count] {
        kept[k] = true;
        in_shell[k] = true;
    }
    // The inside: the rest by rank, enlarged to keep its leaf area.
    let mut inside: Vec<usize> = by_outer[shell_count..].to_vec();
    inside.sort_by(|&a, &b| {
        keep_rank(o.seed, a)
            .total_cmp(&keep_rank(o.seed, b))
            .then(a.cmp(&b))
    });
    for &k in &inside[..m - shell_count] {
        kept[k] = true;
    }
    let grow_inside = if m > shell_count {
        let r = (n - shell_count) as f32 / (m - shell_count) as f32;
        // The square root exactly where the power is a half (its rounding, not powf's).
        if o.keep_enlarge == 0.5 {
            r.sqrt()
        } else {
            libm::powf(r, o.keep_enlarge)
        }
    } else {
        1.0
    };
    Ok(all
        .iter()
        .enumerate()
        .filter(|&(k, _)| kept[k])
        .map(|(k, &(mut l, b))| {
            let grow = if in_shell[k] { 1.0 } else { grow_inside };
            if grow != 1.0 {
                // Enlarged about the leaf's middle, not its stem.
                let q = Quat::from_array(l.rotation);
                let shift = q * (middle * (l.scale * (grow - 1.0)));
                l.position = (Vec3::from(l.position) - shift).to_array();
                l.scale *= grow;
            }
            (l, b, k)
        })
        .collect())
}

/// How far out each leaf is: its middle's distance from the crown's centre over the
/// farthest leaf's in its direction (a grid of directions), 0..=1.
fn outerness(all: &[(LeafInstance, u32)], middle: Vec3) -> Vec<f32> {
    const BINS: usize = 16;
    let mids: Vec<Vec3> = all
        .iter()
        .map(|(l, _)| Vec3::from(l.position) + Quat::from_array(l.rotation) * (middle * l.scale))
        .collect();
    let centre = mids.iter().fold(Vec3::ZERO, |c, &p| c + p) / mids.len().max(1) as f32;
    let bin = |d: Vec3| -> usize {
        let s = (d.x.abs() + d.y.abs() + d.z.abs()).max(f32::MIN_POSITIVE);
        let (mut x, mut y) = (d.x / s, d.z / s);
        if d.y < 0.0 {
            let (ox, oy) = (x, y);
            x = (1.0 - oy.abs()) * if ox < 0.0 { -1.0 } else { 1.0 };
            y = (1.0 - ox.abs()) * if oy < 0.0 { -1.0 } else { 1.0 };
        }
        let cx = (((x * 0.5 + 0.5) * BINS as f32) as usize).min(BINS - 1);
        let cy = (((y * 0.5 + 0.5) * BINS as f32) as usize).min(BINS - 1);
        cy * BINS + cx
    };
    let mut far = vec![0.0f32; BINS * BINS];
    let at: Vec<(usize, f32)> = mids
        .iter()
        .map(|&p| (bin(p - centre), (p - centre).length()))
        .collect();
    for &(b, d) in &at {
        far[b] = far[b].max(d);
    }
    at.iter()
        .map(|&(b, d)| if far[b] > 0.0 { d / far[b] } else { 1.0 })
        .collect()
}

/// The share of a thinned crown's leaves taken from its shell, unenlarged.
const SHELL_SHARE: f32 = 0.85;

/// The points of a leaf shape tested against the wood: every vertex of a small shape (the
/// quad, the folded card), else the corners of its bounding box; and its centre.
fn leaf_points(prefab: &LeafPrefab) -> Vec<Vec3> {
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for v in &prefab.vertices {
        lo = lo.min(Vec3::from(v.position));
        hi = hi.max(Vec3::from(v.position));
    }
    if prefab.vertices.is_empty() {
        return Vec::new();
    }
    let mut points: Vec<Vec3> = if prefab.vertices.len() <= 16 {
        prefab
            .vertices
            .iter()
            .map(|v| Vec3::from(v.position))
            .collect()
    } else {
        (0..8)
            .map(|k| {
                Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect()
    };
    points.push(0.5 * (lo + hi));
    points
}

/// The branches thicker than a radius, bucketed on a grid of cells about as large as
/// the thickest of them, for point-in-wood tests.
struct Wood<'a> {
    branches: &'a [crate::skeleton::Branch],
    cell: f32,
    grid: rustc_hash::FxHashMap<glam::IVec3, Vec<u32>>,
}

impl<'a> Wood<'a> {
    fn new(skeleton: &'a Skeleton, thicker_than: f32) -> Self {
        let branches = skeleton.branches();
        let thick = |b: &crate::skeleton::Branch| b.start_radius.max(b.end_radius) > thicker_than;
        let widest = branches
            .iter()
            .filter(|b| thick(b))
            .map(|b| b.start_radius.max(b.end_radius))
            .fold(0.0f32, f32::max);
        let cell = (4.0 * widest).max(f32::MIN_POSITIVE);
        let mut wood = Wood {
            branches,
            cell,
            grid: Default::default(),
        };
        for (i, b) in branches.iter().enumerate().filter(|(_, b)| thick(b)) {
            let r = b.start_radius.max(b.end_radius);
            let (s, e) = (b.start(), b.end());
            let (lo, hi) = (wood.key(s.min(e) - r), wood.key(s.max(e) + r));
            // A branch far longer than the cells (a bad skeleton) is not bucketed cell
            // by cell: at most 4,096 cells each.
            let span = (hi - lo + 1).as_i64vec3();
            if span.x * span.y * span.z > 4096 {
                continue;
            }
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    for x in lo.x..=hi.x {
                        wood.grid
                            .entry(glam::IVec3::new(x, y, z))
                            .or_default()
                            .push(i as u32);
                    }
                }
            }
        }
        wood
    }

    fn key(&self, p: Vec3) -> glam::IVec3 {
        (p / self.cell).floor().as_ivec3()
    }

    /// Whether any of `points` of leaf `l` (leaf space) is inside a thick branch.
    fn holds(&self, l: &LeafInstance, points: &[Vec3]) -> bool {
        let (q, at) = (Quat::from_array(l.rotation), Vec3::from(l.position));
        points.iter().any(|&p| {
            let p = at + q * (p * l.scale);
            self.grid.get(&self.key(p)).is_some_and(|near| {
                near.iter().any(|&i| {
                    let b = &self.branches[i as usize];
                    let (s, d) = (b.start(), b.end() - b.start());
                    let t = ((p - s).dot(d) / d.length_squared().max(1e-30)).clamp(0.0, 1.0);
                    let r = b.start_radius + (b.end_radius - b.start_radius) * t;
                    (p - (s + d * t)).length() < r
                })
            })
        })
    }
}

/// Every product that sizes a leaf, checked as it is formed: a leaf's own size (before
/// the mesh's scale, which may be tiny) and its reach in the output stay in the f32 range.
fn check_sizes(skeleton: &Skeleton, o: &LeafOptions, mesh: &MeshOptions) -> Result<()> {
    let extent = o
        .prefab
        .as_ref()
        .map_or(1.0f64, |p| {
            p.vertices
                .iter()
                .flat_map(|v| v.position)
                .fold(0.0f64, |a, x| a.max(x.abs() as f64))
        })
        .max(1.0);
    let own = o.size as f64 * (1.0 + o.size_jitter as f64) * extent;
    if own > f32::MAX as f64 / 16.0 {
        return Err(Error::invalid(
            "size",
            format!(
                "{}; a leaf would be {own:e} units before the mesh's scale (size x (1 + \
                 size_jitter) x the prefab's extent), past the f32 range",
                o.size
            ),
        ));
    }
    let largest = own * mesh.out().scale as f64;
    let far = skeleton
        .bounds()
        .map_or(0.0, |(lo, hi)| lo.abs().max(hi.abs()).max_element() as f64)
        * mesh.out().scale as f64;
    // The same bound as the bark's (its tips reach one radius past the tree), so a mesh
    // that may be written may carry its leaves.
    if largest + far > f32::MAX as f64 / 4.0 {
        return Err(Error::invalid(
            "size",
            format!(
                "{}; a leaf would reach {:e} units (size x (1 + size_jitter) x scale), past the f32 range",
                o.size,
                largest + far
            ),
        ));
    }
    Ok(())
}

/// Places leaves one by one, each with its jitter from one seeded stream.
struct Placer<'a> {
    o: &'a LeafOptions,
    rng: Rng,
    out: Vec<(LeafInstance, u32)>,
}

impl Placer<'_> {
    /// A leaf on `branch` at `position`, along `heading` with `up`, leaning `lean`
    /// degrees; at most `max_leaves`, stored fallibly.
    fn leaf(
        &mut self,
        branch: u32,
        position: Vec3,
        heading: Vec3,
        up: Vec3,
        lean: f32,
    ) -> Result<()> {
        let (o, out) = (self.o, &mut self.out);
        if out.len() >= o.max_leaves {
            return Err(Error::LimitExceeded {
                limit_name: "max_leaves",
                what: "leaves",
                limit: o.max_leaves as u64,
                requested: o.max_leaves as u64 + 1,
                step: None,
            });
        }
        if out.len() == out.capacity() {
            out.try_reserve(out.len().max(256))
                .map_err(|_| Error::OutOfMemory {
                    what: format!("the leaf instances ({} and more)", out.len()),
                })?;
        }
        let heading = heading.try_normalize().unwrap_or(Vec3::Y);
        let up = (up - heading * up.dot(heading))
            .try_normalize()
            .unwrap_or_else(|| ring_basis(heading.as_dvec3()).0.as_vec3());
        // Facing the light: the up vector made the world's up, square to the heading
        // (a leaf pointing straight up or down keeps its own).
        let up = if o.face_light {
            (Vec3::Y - heading * heading.y)
                .try_normalize()
                .unwrap_or(up)
        } else {
            up
        };
        // Leaf space: +Y along the heading, +Z the up vector, +X = Y × Z.
        let frame = Quat::from_mat3(&Mat3::from_cols(heading.cross(up), heading, up));
        let spin = (self.rng.next_f64() as f32 * 2.0 - 1.0) * o.rotation_jitter;
        let grow = 1.0 + (self.rng.next_f64() as f32 * 2.0 - 1.0) * o.size_jitter;
        let rotation = (crate::geom::rotation::axis_angle(heading, spin.to_radians())
            * frame
            * crate::geom::rotation::axis_angle(Vec3::X, lean.to_radians()))
        .normalize();
        out.push((
            LeafInstance {
                position: position.to_array(),
                rotation: rotation.to_array(),
                scale: o.size * grow,
            },
            branch,
        ));
        Ok(())
    }
}

/// The leaf instances of `skeleton` (sites first, then tips in branch order), with the
/// output conventions of `mesh` (up axis and uniform scale) applied.
pub fn leaf_instances(
    skeleton: &Skeleton,
    leaves: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<Vec<LeafInstance>> {
    let mut out = place(skeleton, leaves, mesh)?;
    let o = mesh.out();
    if o.map != AxisMap::IDENTITY || o.scale != 1.0 {
        let rotate = o.map.rotation();
        for l in &mut out {
            l.position = o.pos(Vec3::from(l.position));
            l.rotation = rotate(Quat::from_array(l.rotation)).to_array();
            l.scale *= o.scale;
        }
    }
    Ok(out)
}

/// Animation data per leaf instance (same order as [`leaf_instances`]): the values of the
/// tip of the branch each leaf sits on, so leaves grow and sway with their branch.
/// `mesh` says which branches are kept (its `cull_radius`).
pub fn leaf_animation(
    skeleton: &Skeleton,
    leaves: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<Vec<AnimationVertex>> {
    let (start, total) = growth_times(skeleton);
    let b = skeleton.branches();
    Ok(place_kept(skeleton, leaves, mesh)?
        .into_iter()
        .map(|(_, branch, _)| match b.get(branch as usize) {
            Some(x) => AnimationVertex {
                growth: (start[branch as usize] + 1.0) / total,
                order: x.order as f32,
                along: 1.0,
                phase: branch_phase(branch),
            },
            None => AnimationVertex {
                growth: 1.0,
                ..Default::default()
            },
        })
        .collect())
}

/// What the baked leaf mesh holds.
struct LeafPlan {
    /// Each leaf, with its index among all the leaves (before `keep` thins them).
    instances: Vec<(LeafInstance, usize)>,
    /// Atlas columns and rows, and the seed that picks each leaf's cell.
    atlas: (u32, u32, u64),
    prefab: std::sync::Arc<LeafPrefab>,
    /// Polygons to triangulate: (first point, count).
    polygons: Vec<(usize, usize)>,
    /// Whether the skeleton's spheres and discs are in the mesh.
    organs: bool,
    /// Sides of a sphere or disc, and a sphere's latitude bands.
    sides: usize,
    bands: usize,
    size: MeshSize,
    rules: StripRules,
}

fn leaf_plan(skeleton: &Skeleton, leaves: &LeafOptions, mesh: &MeshOptions) -> Result<LeafPlan> {
    // The conventions are applied to the baked vertices, so place in model space.
    leaf_plan_from(skeleton, place_kept(skeleton, leaves, mesh)?, leaves, mesh)
}

/// The plan of the leaf mesh of `kept` (placed and thinned leaves).
fn leaf_plan_from(
    skeleton: &Skeleton,
    kept: Vec<(LeafInstance, u32, usize)>,
    leaves: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<LeafPlan> {
    let instances: Vec<(LeafInstance, usize)> = kept.into_iter().map(|(l, _, k)| (l, k)).collect();
    let prefab = leaves.shape();
    let polygons: Vec<(usize, usize)> = if leaves.polygons {
        skeleton
            .polygons()
            .iter()
            .map(|p| (p.first as usize, p.count as usize))
            .collect()
    } else {
        Vec::new()
    };
    let rules = StripRules {
        topology: mesh.topology,
        clockwise: mesh.reversed(),
    };
    // Every prefab triangle is a strip of 3; only the buffer's first strip differs.
    let triangles = instances.len() as u64 * prefab.triangles.len() as u64;
    let mut first = triangles == 0;
    let mut indices = match triangles {
        0 => 0,
        t => rules.count(3, true) as u64 + (t - 1) * rules.count(3, false) as u64,
    };
    for &(_, n) in &polygons {
        indices += rules.count(n, first) as u64;
        first = false;
    }
    // Spheres (latitude bands, each one strip) and discs (a zig-zag strip), with the
    // sides of the branches.
    let organs = leaves.polygons && !skeleton.organs().is_empty();
    let sides = mesh.radial_segments.max(3) as usize;
    let bands = (sides / 2).max(2);
    let mut organ_vertices = 0u64;
    if organs {
        for o in skeleton.organs() {
            if o.kind == crate::skeleton::ORGAN_SPHERE {
                organ_vertices += ((bands + 1) * (sides + 1)) as u64;
                for _ in 0..bands {
                    indices += rules.count(2 * (sides + 1), first) as u64;
                    first = false;
                }
            } else {
                organ_vertices += sides as u64;
                indices += rules.count(sides, first) as u64;
                first = false;
            }
        }
    }
    let vertices = (instances.len() * prefab.vertices.len()
        + polygons.iter().map(|p| p.1).sum::<usize>()) as u64
        + organ_vertices;
    if vertices > RESTART_INDEX as u64 || indices > u32::MAX as u64 {
        return Err(Error::LimitExceeded {
            limit_name: "u32 index range",
            what: "leaf vertices",
            limit: RESTART_INDEX as u64,
            requested: vertices.max(indices),
            step: None,
        });
    }
    Ok(LeafPlan {
        atlas: (leaves.atlas_columns, leaves.atlas_rows, leaves.seed),
        instances,
        prefab,
        polygons,
        organs,
        sides,
        bands,
        size: MeshSize {
            vertices: vertices as usize,
            indices: indices as usize,
        },
        rules,
    })
}

/// Exact counts of the baked leaf mesh ([`write_leaf_mesh`]).
pub fn leaf_mesh_size(
    skeleton: &Skeleton,
    leaves: &LeafOptions,
    mesh: &MeshOptions,
) -> Result<MeshSize> {
    Ok(leaf_plan(skeleton, leaves, mesh)?.size)
}

/// The baked leaf mesh as owned buffers.
pub fn leaf_mesh(skeleton: &Skeleton, leaves: &LeafOptions, mesh: &MeshOptions) -> Result<Mesh> {
    baked(skeleton, mesh, &leaf_plan(skeleton, leaves, mesh)?)
}

/// The leaf mesh of `plan` as owned buffers.
fn baked(skeleton: &Skeleton, mesh: &MeshOptions, plan: &LeafPlan) -> Result<Mesh> {
    let mut vertices =
        crate::limits::try_zeroed::<Vertex>(plan.size.vertices, "the leaf mesh's vertices")?;
    let mut indices =
        crate::limits::try_zeroed::<u32>(plan.size.indices, "the leaf mesh's indices")?;
    write_leaves(skeleton, mesh, plan, &mut vertices, &mut indices);
    Ok(Mesh {
        vertices,
        indices,
        topology: mesh.topology,
        ranges: Vec::new(),
    })
}

/// Writes the baked leaf mesh (every leaf a copy of the prefab, then every polygon) into
/// caller memory, with the topology and conventions of `mesh`. Too-small slices give
/// [`Error::BufferTooSmall`] and nothing is written.
pub fn write_leaf_mesh(
    skeleton: &Skeleton,
    leaves: &LeafOptions,
    mesh: &MeshOptions,
    vertices: &mut [MaybeUninit<Vertex>],
    indices: &mut [MaybeUninit<u32>],
) -> Result<MeshSize> {
    let plan = leaf_plan(skeleton, leaves, mesh)?;
    let size = plan.size;
    size.check_capacity(vertices.len(), indices.len())?;
    write_leaves(
        skeleton,
        mesh,
        &plan,
        &mut vertices[..size.vertices],
        &mut indices[..size.indices],
    );
    Ok(size)
}

fn write_leaves<V: Slot<Vertex>, I: Slot<u32>>(
    skeleton: &Skeleton,
    mesh: &MeshOptions,
    plan: &LeafPlan,
    vertices: &mut [V],
    indices: &mut [I],
) {
    let mut w = LeafWriter {
        o: mesh.out(),
        vertices,
        vi: 0,
        strips: StripWriter::new(indices, plan.rules, true),
        strip: Vec::new(),
    };
    w.instances(plan);
    w.polygons(skeleton, plan);
    if plan.organs {
        w.organs(skeleton, plan);
    }
    debug_assert_eq!(w.vi, w.vertices.len());
    debug_assert_eq!(w.strips.pos, w.strips.out.len());
}

/// Writes the leaf mesh's parts one after another: vertices from `vi` on, strips through
/// one writer (joined as the topology asks).
struct LeafWriter<'a, V: Slot<Vertex>, I: Slot<u32>> {
    o: super::rings::Out,
    vertices: &'a mut [V],
    vi: usize,
    strips: StripWriter<'a, I>,
    /// Scratch for one strip's indices.
    strip: Vec<u32>,
}

impl<V: Slot<Vertex>, I: Slot<u32>> LeafWriter<'_, V, I> {
    /// One vertex in model space, written with the output conventions.
    #[inline]
    fn put(&mut self, position: Vec3, normal: Vec3, uv: [f32; 2]) {
        self.vertices[self.vi].put(Vertex {
            position: self.o.pos(position),
            normal: self.o.dir(normal),
            uv,
        });
        self.vi += 1;
    }

    /// Every leaf instance a copy of the prefab.
    fn instances(&mut self, plan: &LeafPlan) {
        let (columns, rows, seed) = plan.atlas;
        let cells = columns * rows;
        for &(ref l, k) in &plan.instances {
            let q = Quat::from_array(l.rotation);
            let at = Vec3::from(l.position);
            let base = self.vi as u32;
            // The leaf's atlas cell (with one cell, the prefab's uv as it is).
            let cell = cell_of(seed, cells, k);
            let (cu, cv) = ((cell % columns) as f32, (cell / columns) as f32);
            let (su, sv) = (columns as f32, rows as f32);
            for v in &plan.prefab.vertices {
                let uv = if cells > 1 {
                    [(cu + v.uv[0]) / su, (cv + v.uv[1]) / sv]
                } else {
                    v.uv
                };
                let position = at + q * (Vec3::from(v.position) * l.scale);
                self.put(
                    position,
                    // A prefab's normal may be of any length, even zero (an OBJ file's):
                    // the leaf's face normal stands in for one without a direction.
                    unit(q * Vec3::from(v.normal)).unwrap_or_else(|| q * Vec3::Z),
                    uv,
                );
            }
            for t in &plan.prefab.triangles {
                self.strips.strip(&[base + t[0], base + t[1], base + t[2]]);
            }
        }
    }

    /// Every polygon of the turtle as a convex fan, with Newell's normal and uv over its
    /// bounding rectangle in its own plane.
    fn polygons(&mut self, skeleton: &Skeleton, plan: &LeafPlan) {
        let points = skeleton.polygon_points();
        for &(first, n) in &plan.polygons {
            let pts = &points[first..first + n];
            let at = |k: usize| Vec3::from(pts[k]);
            // Newell's normal: the side from which the points turn counter-clockwise.
            let mut normal = Vec3::ZERO;
            for k in 0..n {
                let (a, b) = (at(k), at((k + 1) % n));
                normal += Vec3::new(
                    (a.y - b.y) * (a.z + b.z),
                    (a.z - b.z) * (a.x + b.x),
                    (a.x - b.x) * (a.y + b.y),
                );
            }
            // `unit`, not `try_normalize`: a nearly flat polygon's sum underflows, and
            // glam would scale it by a reciprocal taken from a subnormal (not unit).
            let e1 = unit(at(1) - at(0)).unwrap_or(Vec3::X);
            let normal = unit(normal).unwrap_or_else(|| e1.any_orthonormal_vector());
            let e2 = normal.cross(e1);
            let plane = |p: Vec3| glam::Vec2::new((p - at(0)).dot(e1), (p - at(0)).dot(e2));
            let (mut lo, mut hi) = (glam::Vec2::splat(f32::MAX), glam::Vec2::splat(f32::MIN));
            for k in 0..n {
                lo = lo.min(plane(at(k)));
                hi = hi.max(plane(at(k)));
            }
            let span = (hi - lo).max(glam::Vec2::splat(f32::MIN_POSITIVE));
            let base = self.vi as u32;
            for k in 0..n {
                self.put(at(k), normal, ((plane(at(k)) - lo) / span).to_array());
            }
            // A convex polygon as a zig-zag strip.
            zigzag(n, |k| base + k as u32, &mut self.strip);
            self.strips.strip(&self.strip);
        }
    }

    /// Every organ: a sphere (latitude bands from the heading) or a disc facing it.
    fn organs(&mut self, skeleton: &Skeleton, plan: &LeafPlan) {
        // Circle tables once per mesh: no trigonometry per vertex.
        let (sides, bands) = (plan.sides, plan.bands);
        let around: Vec<(f32, f32)> = (0..=sides)
            .map(|k| {
                let a = std::f32::consts::TAU * k as f32 / sides as f32;
                (a.cos(), a.sin())
            })
            .collect();
        let down: Vec<(f32, f32)> = (0..=bands)
            .map(|i| match i {
                // The poles exactly, so their triangles collapse to nothing.
                0 => (1.0, 0.0),
                i if i == bands => (-1.0, 0.0),
                i => {
                    let a = std::f32::consts::PI * i as f32 / bands as f32;
                    (a.cos(), a.sin())
                }
            })
            .collect();
        for o in skeleton.organs() {
            let c = Vec3::from(o.position);
            let h = unit(Vec3::from(o.heading)).unwrap_or(Vec3::Y);
            let u = unit(Vec3::from(o.up)).unwrap_or(Vec3::Z);
            // L = H x U: U turning toward L is counter-clockwise about H.
            // The cross product of nearly parallel vectors is mostly rounding: kept only
            // where it stands square to H, so that H, U, L are orthonormal.
            let l = unit(h.cross(u))
                .filter(|l| l.dot(h).abs() < 1e-3)
                .unwrap_or_else(|| h.any_orthonormal_vector());
            let u = l.cross(h);
            let r = 0.5 * o.size;
            let base = self.vi as u32;
            if o.kind == crate::skeleton::ORGAN_SPHERE {
                // Poles on the heading; latitude i from +H, longitude k from U toward L.
                for (i, &(ct, st)) in down.iter().enumerate() {
                    for (k, &(cp, sp)) in around.iter().enumerate() {
                        let n = h * ct + (u * cp + l * sp) * st;
                        self.put(
                            c + n * r,
                            n,
                            [k as f32 / sides as f32, i as f32 / bands as f32],
                        );
                    }
                }
                let ring = (sides + 1) as u32;
                for i in 0..bands as u32 {
                    self.strip.clear();
                    for k in 0..ring {
                        self.strip.push(base + i * ring + k);
                        self.strip.push(base + (i + 1) * ring + k);
                    }
                    self.strips.strip(&self.strip);
                }
            } else {
                for &(cp, sp) in &around[..sides] {
                    self.put(
                        c + (u * cp + l * sp) * r,
                        h,
                        [0.5 + 0.5 * cp, 0.5 + 0.5 * sp],
                    );
                }
                zigzag(sides, |k| base + k as u32, &mut self.strip);
                self.strips.strip(&self.strip);
            }
        }
    }
}
