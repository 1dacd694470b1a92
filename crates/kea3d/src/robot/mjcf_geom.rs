//! MJCF geoms: a geom's shape (`type`, `size`, `fromto`, meshes; an ellipsoid as a hull), its
//! pose, collision bits, friction and `condim`, mass or density and contact skin, and the
//! soft contact parameters the file's geoms give (`mjcf_soft.rs`), one set for all.

use super::mesh;
use super::mjcf::Reader;
use super::mjcf_defaults::Element;
use super::spec::{GeomShape, GeomSpec, Pose};
use super::xml::above;
use super::ImportError;
use kea::{Quat, Real, Vec3};
use roxmltree::Node;

impl Reader<'_, '_> {
    pub(super) fn read_geom(
        &self,
        node: Node<'_, '_>,
        class: &str,
        static_body: bool,
    ) -> Result<GeomSpec, ImportError> {
        let el = self.element(node, class)?;
        let mut pose = Pose::new(
            el.vec3("pos")?.unwrap_or(Vec3::ZERO),
            el.orientation(&self.compiler)?,
        );
        let shape = self.geom_shape(&el, &mut pose, static_body)?;
        let bits = |attr: &str| -> Result<u32, ImportError> {
            match el.number(attr)? {
                None => Ok(1),
                Some(v) if v >= 0.0 && v.fract() == 0.0 && v <= u32::MAX as Real => Ok(v as u32),
                Some(v) => Err(el.error(format!(
                    "`{attr}` = {v}: expected a non-negative whole number"
                ))),
            }
        };
        // MuJoCo's default sliding friction is 1; torsional and rolling are not simulated.
        let friction = match el.up_to::<3>("friction")? {
            Some((f, _)) if f[0] >= 0.0 && f[0].is_finite() => f[0],
            Some((f, _)) => {
                return Err(el.error(format!("`friction` = {}: must be finite and >= 0", f[0])))
            }
            None => 1.0,
        };
        let condim = match el.number("condim")? {
            None => 3,
            Some(c) if c == 1.0 || c == 3.0 => c as u32,
            // Read as given; the caller says that its torsion and rolling are dropped.
            Some(c) if c == 4.0 || c == 6.0 => c as u32,
            Some(c) => return Err(el.error(format!("`condim` = {c}: must be 1, 3, 4 or 6"))),
        };
        self.read_contact_model(&el)?;
        let density = el.number("density")?;
        let mass = el.number("mass")?;
        if let Some(d) = density.filter(|d| *d < 0.0) {
            return Err(el.error(format!("`density` = {d}: must be >= 0")));
        }
        if let Some(m) = mass.filter(|m| *m < 0.0) {
            return Err(el.error(format!("`mass` = {m}: must be >= 0")));
        }
        Ok(GeomSpec {
            shape,
            pose,
            groups: bits("contype")?,
            mask: bits("conaffinity")?,
            friction: Some(friction),
            condim: Some(condim),
            density,
            mass,
            skin: (el.number("margin")?.unwrap_or(0.0) - el.number("gap")?.unwrap_or(0.0)).max(0.0),
        })
    }

    /// A geom's shape from its `type`, `size`, `fromto` (which replaces `pose`) or mesh.
    fn geom_shape(
        &self,
        el: &Element<'_>,
        pose: &mut Pose,
        static_body: bool,
    ) -> Result<GeomShape, ImportError> {
        let kind = el.text("type").unwrap_or("sphere");
        let size = el.up_to::<3>("size")?;
        let need = |k: usize| -> Result<[Real; 3], ImportError> {
            match size {
                Some((s, n)) if n >= k && s[..k].iter().all(|&v| v > 0.0) => Ok(s),
                Some((s, _)) => {
                    Err(el.error(format!("a {kind} needs {k} positive sizes, found {s:?}")))
                }
                None => Err(el.error(format!("a {kind} needs `size`"))),
            }
        };
        let fromto = el.numbers::<6>("fromto")?;
        let along = |pose: &mut Pose, half_from_size: Real| -> Result<Real, ImportError> {
            let Some(f) = fromto else {
                return Ok(half_from_size);
            };
            let (a, b) = (Vec3::new(f[0], f[1], f[2]), Vec3::new(f[3], f[4], f[5]));
            let d = b - a;
            if !above(d.length(), 1e-9) {
                return Err(el.error("`fromto` ends coincide"));
            }
            *pose = Pose::new(
                (a + b) * 0.5,
                Quat::from_rotation_arc(Vec3::Z, d.normalize()),
            );
            Ok(0.5 * d.length())
        };
        Ok(match kind {
            "sphere" => GeomShape::Sphere(need(1)?[0]),
            "capsule" | "cylinder" => {
                let s = need(1)?;
                let half = along(pose, s[1])?;
                if !above(half, 0.0) {
                    return Err(el.error(format!("a {kind} needs a half-length (size's 2nd number) or fromto")));
                }
                if kind == "capsule" {
                    GeomShape::Capsule { radius: s[0], half_length: half }
                } else {
                    GeomShape::Cylinder { radius: s[0], half_length: half }
                }
            }
            "box" => GeomShape::Cuboid(Vec3::from_array(need(3)?)),
            "ellipsoid" => GeomShape::Hull(ellipsoid_points(Vec3::from_array(need(3)?)), Vec::new()),
            "plane" => {
                if !static_body {
                    return Err(el.error("a plane can only belong to the worldbody or a static body"));
                }
                GeomShape::Plane
            }
            "mesh" => {
                let Some(name) = el.text("mesh") else {
                    return Err(el.error("a mesh geom needs `mesh`"));
                };
                let (path, scale) = self
                    .meshes
                    .get(name)
                    .ok_or_else(|| el.error(format!("no mesh asset named \"{name}\"")))?;
                let m = mesh::load(path, *scale).map_err(|e| el.error(e.to_string()))?;
                if self.options.meshes_as_trimesh {
                    GeomShape::Mesh(m.vertices, m.triangles)
                } else {
                    GeomShape::Hull(m.vertices, m.triangles)
                }
            }
            other => return Err(el.error(format!("geom type \"{other}\" is not supported (sphere, capsule, cylinder, box, ellipsoid, plane, mesh)"))),
        })
    }
}

impl Reader<'_, '_> {
    /// A geom's `solref` and `solimp`, kept as the model's contact parameters when they are
    /// the first given (a later geom with others is reported).
    fn read_contact_model(&self, el: &Element<'_>) -> Result<(), ImportError> {
        let Some(s) = super::mjcf_soft::contact_model(el)? else {
            return Ok(());
        };
        match self.contact.get() {
            None => self.contact.set(Some(s)),
            Some(first) if first != s => self.contact_mixed.set(true),
            Some(_) => {}
        }
        Ok(())
    }
}

/// Points on an ellipsoid of these radii, for its convex hull.
fn ellipsoid_points(r: Vec3) -> Vec<Vec3> {
    let (rings, segments) = (8, 16);
    let mut points = vec![Vec3::new(0.0, 0.0, r.z), Vec3::new(0.0, 0.0, -r.z)];
    for i in 1..rings {
        let theta = kea::PI_REAL * i as Real / rings as Real;
        for k in 0..segments {
            let phi = 2.0 * kea::PI_REAL * k as Real / segments as Real;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            points.push(d * r);
        }
    }
    points
}
