//! MJCF's `<compiler>` settings and `<default>` classes: where an element's attribute comes
//! from when the element does not set it (its class, the class's ancestors, then MuJoCo's own
//! default), and how its frame and angles are read.

use super::xml::{above, children, Source};
use super::ImportError;
use kea::{Quat, Real, Vec3};
use roxmltree::Node;
use std::collections::HashMap;

/// The `<compiler>` settings that change how numbers read.
#[derive(Debug, Clone)]
pub(crate) struct Compiler {
    /// Angles in degrees (MuJoCo's default) rather than radians.
    pub degrees: bool,
    /// Euler sequence: three of `xyzXYZ` (lower case: axes that turn with the body).
    pub euler_sequence: [u8; 3],
    /// `true`: mass from geometry even where `inertial` is given; `false`: never; `auto`.
    pub inertia_from_geom: Option<bool>,
    /// Joints with a range but no `limited` are limited.
    pub auto_limits: bool,
    pub meshdir: Option<String>,
    /// `settotalmass`: the model's bodies scaled to this total mass, kg.
    pub total_mass: Option<Real>,
}

impl Compiler {
    pub fn read(src: &Source<'_>, root: Node<'_, '_>) -> Result<Self, ImportError> {
        let mut c = Compiler {
            degrees: true,
            euler_sequence: *b"xyz",
            inertia_from_geom: None,
            auto_limits: true,
            meshdir: None,
            total_mass: None,
        };
        for node in children(root, "compiler") {
            if let Some(a) = node.attribute("angle") {
                c.degrees = match a {
                    "degree" => true,
                    "radian" => false,
                    _ => {
                        return Err(
                            src.error(node, format!("angle=\"{a}\": expected degree or radian"))
                        )
                    }
                };
            }
            if let Some(s) = node.attribute("eulerseq") {
                let b = s.as_bytes();
                if b.len() != 3 || !b.iter().all(|ch| b"xyzXYZ".contains(ch)) {
                    return Err(src.error(
                        node,
                        format!("eulerseq=\"{s}\": expected three of x, y, z, X, Y, Z"),
                    ));
                }
                c.euler_sequence = [b[0], b[1], b[2]];
            }
            if let Some(a) = node.attribute("inertiafromgeom") {
                c.inertia_from_geom = match a {
                    "true" => Some(true),
                    "false" => Some(false),
                    "auto" => None,
                    _ => {
                        return Err(src.error(
                            node,
                            format!("inertiafromgeom=\"{a}\": expected true, false or auto"),
                        ))
                    }
                };
            }
            if let Some(a) = node.attribute("autolimits") {
                c.auto_limits = a == "true";
            }
            if let Some(a) = node.attribute("coordinate") {
                if a != "local" {
                    return Err(src.error(node, format!("coordinate=\"{a}\": only local coordinates are supported (MuJoCo removed global ones)")));
                }
            }
            if let Some(t) = src.number(node, "settotalmass")? {
                // MuJoCo: a non-positive value leaves the masses as they are.
                c.total_mass = above(t, 0.0).then_some(t);
            }
            if let Some(d) = node.attribute("meshdir") {
                c.meshdir = Some(d.to_string());
            }
        }
        Ok(c)
    }

    /// An angle as the file writes it, in radians.
    pub fn angle(&self, a: Real) -> Real {
        if self.degrees {
            a.to_radians()
        } else {
            a
        }
    }
}

/// The attributes a class gives each element type, inheritance resolved.
#[derive(Debug, Clone, Default)]
pub(crate) struct Defaults {
    /// class → tag → (attribute → value).
    classes: HashMap<String, HashMap<String, HashMap<String, String>>>,
}

/// The top-level class.
pub(crate) const MAIN: &str = "main";

impl Defaults {
    pub fn read(src: &Source<'_>, root: Node<'_, '_>) -> Result<Self, ImportError> {
        let mut d = Defaults::default();
        d.classes.insert(MAIN.to_string(), HashMap::new());
        for node in children(root, "default") {
            d.read_class(src, node, MAIN, true)?;
        }
        Ok(d)
    }

    fn read_class(
        &mut self,
        src: &Source<'_>,
        node: Node<'_, '_>,
        parent: &str,
        top: bool,
    ) -> Result<(), ImportError> {
        let name = match node.attribute("class") {
            Some(c) => c.to_string(),
            None if top => MAIN.to_string(),
            None => return Err(src.error(node, "a nested <default> needs a class name")),
        };
        let mut own = self.classes.get(parent).cloned().unwrap_or_default();
        for el in node
            .children()
            .filter(|c| c.is_element() && c.tag_name().name() != "default")
        {
            let entry = own.entry(el.tag_name().name().to_string()).or_default();
            for a in el.attributes() {
                entry.insert(a.name().to_string(), a.value().to_string());
            }
        }
        self.classes.insert(name.clone(), own);
        for sub in children(node, "default") {
            self.read_class(src, sub, &name, false)?;
        }
        Ok(())
    }

    /// `node` read with its class (its own `class`, else `class`), refused if unknown.
    pub fn element<'s>(
        &'s self,
        src: &'s Source<'s>,
        node: Node<'s, 's>,
        class: &'s str,
    ) -> Result<Element<'s>, ImportError> {
        let class = match node.attribute("class") {
            Some(c) if self.has(c) => c,
            Some(c) => return Err(src.error(node, format!("no default class \"{c}\""))),
            None => class,
        };
        Ok(Element {
            node,
            class,
            defaults: self,
            src,
            tag: node.tag_name().name(),
        })
    }

    /// Whether a class exists.
    pub fn has(&self, class: &str) -> bool {
        self.classes.contains_key(class)
    }

    /// The default of `attr` for `tag` elements in `class`.
    pub fn get(&self, class: &str, tag: &str, attr: &str) -> Option<&str> {
        self.classes
            .get(class)?
            .get(tag)?
            .get(attr)
            .map(String::as_str)
    }
}

/// An element with its class: reads attributes from the element, else its class.
#[derive(Clone, Copy)]
pub(crate) struct Element<'a> {
    pub node: Node<'a, 'a>,
    pub class: &'a str,
    pub defaults: &'a Defaults,
    pub src: &'a Source<'a>,
    /// The tag whose defaults apply (an actuator's `position` reads `position` defaults).
    pub tag: &'a str,
}

impl<'a> Element<'a> {
    /// The attribute's text: the element's own, else its class's.
    pub fn text(&self, attr: &str) -> Option<&'a str> {
        self.node
            .attribute(attr)
            .or_else(|| self.defaults.get(self.class, self.tag, attr))
    }

    pub fn error(&self, reason: impl Into<String>) -> ImportError {
        self.src.error(self.node, reason)
    }

    /// Exactly `N` numbers, or `None` if neither the element nor its class sets them.
    pub fn numbers<const N: usize>(&self, attr: &str) -> Result<Option<[Real; N]>, ImportError> {
        let Some(text) = self.text(attr) else {
            return Ok(None);
        };
        let values = self.src.list(self.node, attr, text)?;
        if values.len() != N {
            return Err(self.error(format!(
                "`{attr}` = \"{text}\": expected {N} numbers, found {}",
                values.len()
            )));
        }
        let mut out = [0.0; N];
        out.copy_from_slice(&values);
        Ok(Some(out))
    }

    /// Between 1 and `N` numbers (MJCF's `size`), padded with zeros.
    pub fn up_to<const N: usize>(
        &self,
        attr: &str,
    ) -> Result<Option<([Real; N], usize)>, ImportError> {
        let Some(text) = self.text(attr) else {
            return Ok(None);
        };
        let values = self.src.list(self.node, attr, text)?;
        if values.is_empty() || values.len() > N {
            return Err(self.error(format!("`{attr}` = \"{text}\": expected 1 to {N} numbers")));
        }
        let mut out = [0.0; N];
        out[..values.len()].copy_from_slice(&values);
        Ok(Some((out, values.len())))
    }

    pub fn number(&self, attr: &str) -> Result<Option<Real>, ImportError> {
        Ok(self.numbers::<1>(attr)?.map(|[v]| v))
    }

    pub fn non_negative(&self, attr: &str) -> Result<Real, ImportError> {
        let v = self.number(attr)?.unwrap_or(0.0);
        if v < 0.0 {
            return Err(self.error(format!("`{attr}` = {v}: must be >= 0")));
        }
        Ok(v)
    }

    pub fn vec3(&self, attr: &str) -> Result<Option<Vec3>, ImportError> {
        Ok(self.numbers::<3>(attr)?.map(Vec3::from_array))
    }

    /// A true/false attribute (`None`: unset or `auto`).
    pub fn flag(&self, attr: &str) -> Result<Option<bool>, ImportError> {
        match self.text(attr) {
            None | Some("auto") => Ok(None),
            Some("true") => Ok(Some(true)),
            Some("false") => Ok(Some(false)),
            Some(other) => Err(self.error(format!(
                "`{attr}` = \"{other}\": expected true, false or auto"
            ))),
        }
    }

    /// The element's orientation (`quat`, `axisangle`, `euler`, `xyaxes` or `zaxis`), identity
    /// without one; two of them at once are refused.
    pub fn orientation(&self, compiler: &Compiler) -> Result<Quat, ImportError> {
        let given: Vec<&str> = ["quat", "axisangle", "euler", "xyaxes", "zaxis"]
            .into_iter()
            .filter(|a| self.node.attribute(*a).is_some())
            .collect();
        if given.len() > 1 {
            return Err(self.error(format!("orientation given twice: {}", given.join(" and "))));
        }
        let q = if let Some([w, x, y, z]) = self.numbers::<4>("quat")? {
            let q = Quat::from_xyzw(x, y, z, w);
            if !above(q.length(), 1e-9) {
                return Err(self.error("`quat` has zero length"));
            }
            q.normalize()
        } else if let Some([x, y, z, a]) = self.numbers::<4>("axisangle")? {
            let axis = Vec3::new(x, y, z);
            if !above(axis.length(), 1e-9) {
                return Err(self.error("`axisangle` has a zero axis"));
            }
            Quat::from_axis_angle(axis.normalize(), compiler.angle(a))
        } else if let Some(e) = self.numbers::<3>("euler")? {
            euler(e.map(|a| compiler.angle(a)), compiler.euler_sequence)
        } else if let Some(v) = self.numbers::<6>("xyaxes")? {
            let x = Vec3::new(v[0], v[1], v[2]).normalize_or_zero();
            let y0 = Vec3::new(v[3], v[4], v[5]);
            let y = (y0 - x * x.dot(y0)).normalize_or_zero();
            if x == Vec3::ZERO || y == Vec3::ZERO {
                return Err(self.error("`xyaxes` must be two independent directions"));
            }
            Quat::from_mat3(&kea::Mat3::from_cols(x, y, x.cross(y)))
        } else if let Some(z) = self.vec3("zaxis")? {
            if !above(z.length(), 1e-9) {
                return Err(self.error("`zaxis` cannot be zero"));
            }
            Quat::from_rotation_arc(Vec3::Z, z.normalize())
        } else {
            Quat::IDENTITY
        };
        Ok(q)
    }
}

/// Euler angles in MuJoCo's convention: lower-case axes turn with the body (each rotation
/// applied on the right), upper-case ones stay fixed (applied on the left).
fn euler(angles: [Real; 3], sequence: [u8; 3]) -> Quat {
    let mut q = Quat::IDENTITY;
    for (a, ch) in angles.into_iter().zip(sequence) {
        let r = match ch.to_ascii_lowercase() {
            b'x' => Quat::from_rotation_x(a),
            b'y' => Quat::from_rotation_y(a),
            _ => Quat::from_rotation_z(a),
        };
        q = if ch.is_ascii_lowercase() {
            q * r
        } else {
            r * q
        };
    }
    q.normalize()
}
