//! MJCF (MuJoCo's format), the subset real models use: the `worldbody` tree with body frames
//! (`pos`, `quat`, `euler`, `axisangle`, `xyaxes`, `zaxis`, in the compiler's angle unit),
//! `inertial` or mass from geometry, `hinge`/`slide`/`ball`/`free` joints (with `range`,
//! `damping`, `armature`, `frictionloss`, `ref`), geoms (sphere, capsule and cylinder with
//! `size` or `fromto`, box, ellipsoid as a hull, plane, mesh), `default` classes,
//! `contype`/`conaffinity`, and `motor`/`position`/`velocity` actuators on joints.
//!
//! A body with several joints is one Kea joint when they make one: two slides and a hinge
//! about their common normal (a planar root, as in Hopper and Walker2d) or two slides. Joint
//! springs (`stiffness`, `springref`) are read on hinges and slides and refused on ball and
//! free joints; a joint's stops are MuJoCo's soft ones (`solreflimit`, `solimplimit`,
//! `margin`) where it steps in reduced coordinates; `<option>` is `mjcf_option.rs`. What
//! would change the physics and is not read — tendons that apply force (`mjcf_tendon.rs`),
//! joint equalities, contact pairs and exclusions, composites — is refused by name; what does not (lights,
//! cameras, sites, sensors, visual settings) is passed over.

use super::mesh;
use super::mjcf_actuators::ActuatorSpec;
use super::mjcf_defaults::{Compiler, Defaults, Element, MAIN};
use super::mjcf_joints::{combined, JointPart};
use super::spec::{Coordinate, Inertial, JointSpec, JointType, LinkSpec, Pose, RobotSpec};
use super::xml::{above, children, Source};
use super::{ImportError, MjcfOptions};
use kea::{JointDynamics, Mat3, Real, Vec3};
use roxmltree::Node;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// A read MJCF file.
pub(crate) struct MjcfModel {
    pub spec: RobotSpec,
    pub option: super::mjcf_option::MjcfOption,
    pub actuators: Vec<ActuatorSpec>,
    pub equalities: Vec<super::mjcf_equality::EqualitySpec>,
    /// MuJoCo's soft contact parameters (`solref`, `solimp`) its geoms give, or MuJoCo's
    /// defaults: the reduced-coordinate path's contacts follow them.
    pub contact: kea::SoftLimit,
}

/// Top-level sections passed over: they do not change the physics.
const PASSIVE_SECTIONS: [&str; 7] = [
    "visual",
    "statistic",
    "size",
    "custom",
    "sensor",
    "keyframe",
    "extension",
];
/// Top-level sections refused: the model's behaviour depends on them.
const REFUSED_SECTIONS: [&str; 2] = ["contact", "deformable"];

pub(super) struct Reader<'a, 'd> {
    pub(super) src: Source<'a>,
    pub(super) compiler: Compiler,
    pub(super) defaults: Defaults,
    pub(super) meshes: HashMap<String, (PathBuf, Vec3)>,
    pub(super) options: &'a MjcfOptions,
    pub(super) spec: RobotSpec,
    /// The first geom's contact parameters, and whether a later geom gave others.
    pub(super) contact: std::cell::Cell<Option<kea::SoftLimit>>,
    pub(super) contact_mixed: std::cell::Cell<bool>,
    _doc: std::marker::PhantomData<&'d ()>,
}

/// Parses MJCF text; `file` names it in errors and anchors mesh paths.
pub(crate) fn parse(
    text: &str,
    file: &Path,
    options: &MjcfOptions,
) -> Result<MjcfModel, ImportError> {
    let text = super::mjcf_include::expand(&super::xml::tidy(text), file)?;
    let doc = super::xml::parse_document(&text, file)?;
    let src = Source { file, doc: &doc };
    let root = doc.root_element();
    if root.tag_name().name() != "mujoco" {
        return Err(src.error(root, "an MJCF file's root element must be <mujoco>"));
    }
    for section in root.children().filter(|c| c.is_element()) {
        let tag = section.tag_name().name();
        if REFUSED_SECTIONS.contains(&tag) {
            return Err(src.error(
                section,
                format!("<{tag}> is not supported: the model's behaviour depends on it"),
            ));
        }
        let known = [
            "compiler",
            "option",
            "default",
            "asset",
            "worldbody",
            "actuator",
            "equality",
            "tendon",
        ];
        if !known.contains(&tag) && !PASSIVE_SECTIONS.contains(&tag) {
            return Err(src.error(section, format!("<{tag}> is not supported")));
        }
    }
    let compiler = Compiler::read(&src, root)?;
    let defaults = Defaults::read(&src, root)?;
    let mut skipped = Vec::new();
    let option = super::mjcf_option::read(&src, root, &mut skipped)?;
    let mut reader = Reader {
        meshes: HashMap::new(),
        compiler,
        defaults,
        options,
        spec: RobotSpec::new(root.attribute("model").unwrap_or("model"), true),
        src,
        contact: std::cell::Cell::new(None),
        contact_mixed: std::cell::Cell::new(false),
        _doc: std::marker::PhantomData,
    };
    reader.spec.skipped.append(&mut skipped);
    reader.spec.total_mass = reader.compiler.total_mass;
    reader.read_assets(root)?;
    for world in children(root, "worldbody") {
        reader.read_body_contents(world, 0, MAIN)?;
    }
    let actuators = super::mjcf_actuators::read(&reader.src, &reader.defaults, &reader.spec, root)?;
    super::mjcf_tendon::read(
        &reader.src,
        &reader.defaults,
        reader.compiler.auto_limits,
        &mut reader.spec,
        root,
    )?;
    if contacts_disabled(root) {
        // The model asks for no contacts at all: no geometry collides.
        for g in reader
            .spec
            .links
            .iter_mut()
            .flat_map(|l| l.geoms.iter_mut())
        {
            g.groups = 0;
            g.mask = 0;
        }
    }
    let equalities = super::mjcf_equality::read(&reader.src, root, &mut reader.spec.skipped)?;
    if reader.contact_mixed.get() {
        reader.spec.skipped.push(format!(
            "{}: geoms with different `solref`/`solimp`: the first geom's are used for every contact",
            reader.src.file.display()
        ));
    }
    Ok(MjcfModel {
        equalities,
        contact: reader.contact.get().unwrap_or_default(),
        spec: reader.spec,
        option,
        actuators,
    })
}

/// Whether `<option><flag contact="disable"/>` turns contacts off.
fn contacts_disabled(root: Node<'_, '_>) -> bool {
    children(root, "option")
        .flat_map(|o| children(o, "flag"))
        .any(|f| f.attribute("contact") == Some("disable"))
}

impl<'a, 'd> Reader<'a, 'd> {
    pub(super) fn element<'s>(
        &'s self,
        node: Node<'s, 's>,
        class: &'s str,
    ) -> Result<Element<'s>, ImportError> {
        self.defaults.element(&self.src, node, class)
    }

    fn read_assets(&mut self, root: Node<'_, '_>) -> Result<(), ImportError> {
        for asset in children(root, "asset") {
            for m in children(asset, "mesh") {
                let el = self.element(m, MAIN)?;
                let Some(file) = m.attribute("file") else {
                    return Err(self.src.error(
                        m,
                        "a mesh without `file` (inline vertices are not supported)",
                    ));
                };
                let name = m.attribute("name").map(str::to_string).unwrap_or_else(|| {
                    Path::new(file)
                        .file_stem()
                        .map(|s| s.to_string_lossy().into_owned())
                        .unwrap_or_default()
                });
                let scale = el.vec3("scale")?.unwrap_or(Vec3::ONE);
                let mut search = Vec::new();
                if let Some(dir) = &self.compiler.meshdir {
                    let base = self.src.file.parent().unwrap_or(Path::new("."));
                    search.push(base.join(dir));
                }
                search.extend(self.options.mesh_search_path.iter().cloned());
                let path = mesh::resolve(file, self.src.file, &search).ok_or_else(|| {
                    self.src.error(m, format!("mesh file \"{file}\" not found (looked beside the model, in meshdir and the search path)"))
                })?;
                self.meshes.insert(name, (path, scale));
            }
        }
        Ok(())
    }

    /// The geoms and child bodies of a body (or of the worldbody, link 0).
    fn read_body_contents(
        &mut self,
        body: Node<'_, '_>,
        link: usize,
        class: &str,
    ) -> Result<(), ImportError> {
        for c in body.children().filter(|c| c.is_element()) {
            match c.tag_name().name() {
                "geom" => {
                    let g = self.read_geom(c, class, link == 0)?;
                    if let Some(condim @ (4 | 6)) = g.condim {
                        self.spec.skipped.push(format!(
                            "{}:{}: geom: torsional and rolling friction (`condim` = {condim}) \
                             are not simulated: its contacts have sliding friction only",
                            self.src.file.display(),
                            self.src.line(c)
                        ));
                    }
                    self.spec.links[link].geoms.push(g);
                }
                "body" => self.read_body(c, link, class)?,
                "joint" | "freejoint" | "inertial" if link == 0 => {
                    return Err(self
                        .src
                        .error(c, "the worldbody cannot have joints or an inertial"));
                }
                "joint" | "freejoint" | "inertial" => {}
                "site" | "camera" | "light" => {}
                "frame" | "composite" | "flexcomp" | "plugin" | "attach" | "replicate" => {
                    return Err(self
                        .src
                        .error(c, format!("<{}> is not supported", c.tag_name().name())));
                }
                other => {
                    return Err(self
                        .src
                        .error(c, format!("<{other}> is not an element of a body")))
                }
            }
        }
        Ok(())
    }

    fn read_body(
        &mut self,
        body: Node<'_, '_>,
        parent: usize,
        class: &str,
    ) -> Result<(), ImportError> {
        let childclass = match body.attribute("childclass") {
            Some(c) if self.defaults.has(c) => c.to_string(),
            Some(c) => return Err(self.src.error(body, format!("no default class \"{c}\""))),
            None => class.to_string(),
        };
        let el = self.element(body, &childclass)?;
        let pos = el.vec3("pos")?.unwrap_or(Vec3::ZERO);
        let rot = el.orientation(&self.compiler)?;
        let link = self.spec.links.len();
        let name = body
            .attribute("name")
            .map(str::to_string)
            .unwrap_or_else(|| format!("body{link}"));
        if self.spec.links.iter().any(|l| l.name == name) {
            return Err(self
                .src
                .error(body, format!("a second body named \"{name}\"")));
        }
        let inertial = self.read_inertial(body, &childclass)?;
        self.spec.links.push(LinkSpec {
            name: name.clone(),
            line: self.src.line(body),
            inertial,
            geoms: Vec::new(),
        });
        let joints = self.read_joints(body, &childclass, parent, link, Pose::new(pos, rot))?;
        self.spec.joints.extend(joints);
        self.read_body_contents(body, link, &childclass)
    }

    fn read_inertial(
        &self,
        body: Node<'_, '_>,
        class: &str,
    ) -> Result<Option<Inertial>, ImportError> {
        let node = children(body, "inertial").next();
        let use_file = match (self.compiler.inertia_from_geom, node) {
            (Some(true), _) | (None, None) => return Ok(None),
            (Some(false), None) => return Ok(Some(Inertial::NONE)),
            (_, Some(n)) => n,
        };
        let el = self.element(use_file, class)?;
        if el.text("mass").is_none() {
            return Err(el.error("the attribute `mass` is missing (MuJoCo requires it)"));
        }
        let mass = el.non_negative("mass")?;
        let frame = el.orientation(&self.compiler)?;
        let tensor = if let Some(d) = el.vec3("diaginertia")? {
            Mat3::from_diagonal(d)
        } else if let Some([xx, yy, zz, xy, xz, yz]) = el.numbers::<6>("fullinertia")? {
            Mat3::from_cols(
                Vec3::new(xx, xy, xz),
                Vec3::new(xy, yy, yz),
                Vec3::new(xz, yz, zz),
            )
        } else {
            return Err(el.error("an <inertial> needs diaginertia or fullinertia"));
        };
        // MuJoCo refuses what no mass distribution has; so does Kea.
        match super::inertia_check::check(tensor) {
            Err(reason) | Ok(Some(reason)) => return Err(el.error(reason)),
            Ok(None) => {}
        }
        let r = Mat3::from_quat(frame);
        Ok(Some(Inertial {
            mass,
            com: el.vec3("pos")?.unwrap_or(Vec3::ZERO),
            inertia: r * tensor * r.transpose(),
        }))
    }

    /// The body's joints as one joint spec (fixed without any).
    fn read_joints(
        &mut self,
        body: Node<'_, '_>,
        class: &str,
        parent: usize,
        link: usize,
        origin: Pose,
    ) -> Result<Vec<JointSpec>, ImportError> {
        let mut parts: Vec<JointPart<'_>> = Vec::new();
        for j in body.children().filter(|c| c.is_element()) {
            let tag = j.tag_name().name();
            if tag != "joint" && tag != "freejoint" {
                continue;
            }
            let el = self.element(j, class)?;
            let kind: &'static str = if tag == "freejoint" {
                "free"
            } else {
                match el.text("type").unwrap_or("hinge") {
                    "hinge" => "hinge",
                    "slide" => "slide",
                    "ball" => "ball",
                    "free" => "free",
                    other => return Err(el.error(format!("joint type \"{other}\" is not an MJCF joint type (hinge, slide, ball, free)"))),
                }
            };
            let name = j
                .attribute("name")
                .map(str::to_string)
                .unwrap_or_else(|| format!("{}_joint{}", self.spec.links[link].name, parts.len()));
            // MuJoCo refuses a repeated name: actuators and sensors name joints.
            let taken = |n: &str| {
                parts.iter().any(|p| p.0 == n)
                    || self
                        .spec
                        .joints
                        .iter()
                        .any(|o| o.parts.iter().any(|p| p == n))
            };
            if j.attribute("name").is_some() && taken(&name) {
                return Err(el.error(format!("a second joint named \"{name}\"")));
            }
            let (coord, anchor) = self.read_coordinate(&el, kind)?;
            parts.push((name, kind, coord, anchor, j));
        }
        let link_name = self.spec.links[link].name.clone();
        let one_each = parts.len() > 1 && parts.iter().all(|p| matches!(p.1, "hinge" | "slide"));
        let (kind, anchor) = match combined(&self.src, body, &parts, parent, &link_name) {
            Ok(found) => found,
            // Hinges and slides MuJoCo composes in order: a chain of single joints.
            Err(_) if one_each => {
                return Ok(super::mjcf_joints::chain(
                    &mut self.spec,
                    &self.src,
                    &parts,
                    (parent, link),
                    origin,
                ))
            }
            Err(e) => return Err(e),
        };
        for (name, k, c, _, node) in &parts {
            let d = c.dynamics;
            if matches!(*k, "free" | "ball")
                && (d.damping > 0.0 || d.armature > 0.0 || d.friction > 0.0)
            {
                self.spec.skipped.push(format!(
                    "{}:{}: damping, armature and frictionloss of {k} joint \"{name}\": not supported, left out",
                    self.src.file.display(),
                    self.src.line(*node)
                ));
            }
        }
        let names: Vec<String> = parts.iter().map(|p| p.0.clone()).collect();
        Ok(vec![JointSpec {
            line: parts
                .first()
                .map_or(self.src.line(body), |p| self.src.line(p.4)),
            name: names
                .first()
                .cloned()
                .unwrap_or_else(|| format!("{link_name}_weld")),
            parts: names,
            kind,
            parent,
            child: link,
            origin,
            anchor,
            coords: if matches!(kind, JointType::Free | JointType::Ball) {
                Vec::new()
            } else {
                parts.iter().map(|p| p.2).collect()
            },
        }])
    }

    /// One joint's coordinate (axis, range, dynamics, reference) and its point.
    fn read_coordinate(
        &self,
        el: &Element<'_>,
        kind: &str,
    ) -> Result<(Coordinate, Vec3), ImportError> {
        let axis = el.vec3("axis")?.unwrap_or(Vec3::Z);
        if !above(axis.length(), 1e-9) {
            return Err(el.error("`axis` cannot be zero"));
        }
        let angular = kind == "hinge";
        let unit = |v: Real| if angular { self.compiler.angle(v) } else { v };
        let range = el.numbers::<2>("range")?;
        // `autolimits`: a range makes the joint limited, the element's own or its class's.
        let limited = el
            .flag("limited")?
            .unwrap_or(self.compiler.auto_limits && range.is_some());
        let limits = match (limited, range) {
            (true, Some([lo, hi])) if lo < hi => Some((unit(lo), unit(hi))),
            (true, Some([lo, hi])) => {
                return Err(el.error(format!("`range` = {lo} {hi}: lower must be below upper")))
            }
            (true, None) => return Err(el.error("limited=\"true\" needs a `range`")),
            (false, _) => None,
        };
        let stiffness = el.non_negative("stiffness")?;
        if stiffness > 0.0 && matches!(kind, "ball" | "free") {
            return Err(el.error(format!(
                "`stiffness` = {stiffness}: springs on {kind} joints are not supported"
            )));
        }
        let mut c = Coordinate::along(axis.normalize());
        c.limits = if matches!(kind, "ball" | "free") {
            None
        } else {
            limits
        };
        c.reference = unit(el.number("ref")?.unwrap_or(0.0));
        c.dynamics = JointDynamics {
            armature: el.non_negative("armature")?,
            damping: el.non_negative("damping")?,
            stiffness,
            // MuJoCo's spring rests at `springref` (file coordinates); Kea's coordinate is 0
            // at the file's pose, where the file's coordinate is `ref`.
            rest: unit(el.number("springref")?.unwrap_or(0.0)) - c.reference,
            friction: el.non_negative("frictionloss")?,
            soft_limit: super::mjcf_soft::soft_limit(el)?,
        };
        Ok((c, el.vec3("pos")?.unwrap_or(Vec3::ZERO)))
    }
}
