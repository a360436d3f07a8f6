//! SRDF (MoveIt's Semantic Robot Description Format): joint groups, named group states and
//! the allowed-collision matrix that URDF has no place for.
//!
//! - [`Srdf::parse`] / [`Srdf::load_file`] read SRDF text; [`Srdf::apply`] turns its groups
//!   into [`JointGroup`](crate::model::JointGroup)s of a [`Robot`] and its `<disable_collisions>` into allowed pairs.
//! - [`Srdf::from_robot`] / [`Srdf::to_xml`] / [`export`] write a robot's groups and allowed
//!   pairs (adjacent pairs included, reason `Adjacent`, since MoveIt does not assume them), so
//!   URDF + SRDF reload to the same model and MoveIt gets the same collision matrix.
//!
//! Group members are resolved as MoveIt does: `<joint>` by name, `<link>` by its parent
//! joint, `<chain base_link tip_link>` as the joints from base to tip, `<group>` as the joints
//! of another group. Fixed, mimic and `<passive_joint>` joints are dropped (they are not
//! planned degrees of freedom); a `<joint>` naming the `<virtual_joint>` (a mobile base's
//! planar or floating joint, which the model does not have) is dropped and noted in
//! [`SrdfReport::ignored`]; a group left with no degree of freedom (e.g. an end-effector
//! link group) is skipped and listed in [`SrdfReport::skipped_groups`]. Other unknown names
//! are errors.
//!
//! Compatibility with what MoveIt's srdfdom accepts: `<virtual_joint>`, `<passive_joint>` and
//! `<end_effector>` are read ([`Srdf::virtual_joints`], [`Srdf::passive_joints`],
//! [`Srdf::end_effectors`]); elements srdfdom does not know (at the top level or inside a
//! group, such as a `<passive_joint>` written inside a `<group>`) are ignored and listed in
//! [`Srdf::ignored`].
//!
//! Hostile input: the text is checked against [`XmlLimits`] before parsing, and groups are
//! resolved iteratively with memoisation through a name index, so subgroup chains of any
//! length and groups that share subgroups take time linear in the document.
//!
//! ```
//! use opengrasp_core::model::samples;
//! use opengrasp_core::srdf::Srdf;
//!
//! # fn main() -> opengrasp_core::Result<()> {
//! let mut robot = samples::planar_arm(&[0.5, 0.4])?;
//! let text = r#"<robot name="planar">
//!   <group name="elbow"><joint name="joint1"/></group>
//!   <disable_collisions link1="base" link2="link1" reason="Never"/>
//! </robot>"#;
//! let report = Srdf::parse(text)?.apply(&mut robot)?;
//! assert_eq!(report.groups, ["elbow"]);
//! assert_eq!(robot.group("elbow")?.dofs(), &[1]);
//! let (a, b) = (robot.link_id("base")?, robot.link_id("link1")?);
//! assert!(robot.is_collision_allowed(a, b));
//! # Ok(())
//! # }
//! ```

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

use crate::error::{CoreError, Result};
use crate::model::{LinkId, Robot};
use crate::urdf::XmlLimits;

mod resolve;

/// Most groups [`Srdf::apply`] adds to a robot (real configurations have tens; adding a
/// group to a [`Robot`] costs time proportional to its groups, so this bounds a hostile
/// document's cost). [`Srdf::group_joints`] has no such limit.
pub const MAX_GROUPS: usize = 10_000;

/// A `<group>`: its members as written (resolved by [`Srdf::apply`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SrdfGroup {
    /// Group name.
    pub name: String,
    /// `<joint name>` members.
    pub joints: Vec<String>,
    /// `<link name>` members.
    pub links: Vec<String>,
    /// `<chain base_link tip_link>` members.
    pub chains: Vec<(String, String)>,
    /// `<group name>` members (subgroups).
    pub subgroups: Vec<String>,
}

/// A `<group_state>`: named joint values of a group (e.g. `home`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GroupState {
    /// State name.
    pub name: String,
    /// The group it belongs to.
    pub group: String,
    /// Joint values (rad or m).
    pub joints: Vec<(String, f64)>,
}

/// A `<disable_collisions>` entry.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DisabledCollision {
    /// First link.
    pub link1: String,
    /// Second link.
    pub link2: String,
    /// Why (`Adjacent`, `Never`, `Default`, `User`, ...).
    pub reason: String,
}

/// A `<virtual_joint>`: how the robot's root attaches to an external frame.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct VirtualJoint {
    /// Joint name.
    pub name: String,
    /// `fixed`, `planar` or `floating`.
    pub kind: String,
    /// The external frame (`world`, `odom_combined`, ...).
    pub parent_frame: String,
    /// The robot link it moves.
    pub child_link: String,
}

/// An `<end_effector>`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct EndEffector {
    /// End-effector name.
    pub name: String,
    /// The group of its links.
    pub group: String,
    /// The link it is attached to.
    pub parent_link: String,
    /// The group it is attached to, if given.
    pub parent_group: Option<String>,
}

/// The contents of an SRDF document.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Srdf {
    /// The `<robot name>`.
    pub robot: String,
    /// Groups, in document order.
    pub groups: Vec<SrdfGroup>,
    /// Group states, in document order.
    pub group_states: Vec<GroupState>,
    /// Disabled collision pairs, in document order.
    pub disabled_collisions: Vec<DisabledCollision>,
    /// Virtual joints, in document order.
    pub virtual_joints: Vec<VirtualJoint>,
    /// `<passive_joint name>` entries (joints not actuated, left out of groups' degrees of
    /// freedom).
    pub passive_joints: Vec<String>,
    /// End effectors, in document order.
    pub end_effectors: Vec<EndEffector>,
    /// Elements not modelled and ignored, described (`<sphere> at top level`,
    /// `<passive_joint> inside group `hand``), in document order.
    pub ignored: Vec<String>,
}

/// What [`Srdf::apply`] did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SrdfReport {
    /// Groups added to the robot (replacing groups of the same name).
    pub groups: Vec<String>,
    /// Groups without any degree of freedom, not added.
    pub skipped_groups: Vec<String>,
    /// `<disable_collisions>` pairs applied.
    pub allowed_pairs: usize,
    /// Members accepted but not modelled, described (a group naming the virtual joint).
    pub ignored: Vec<String>,
}

fn malformed(reason: impl Into<String>) -> CoreError {
    CoreError::MalformedSrdf { reason: reason.into() }
}

/// The value of attribute `key` of `e`, unescaped.
fn attribute(e: &BytesStart<'_>, key: &str) -> Result<Option<String>> {
    for a in e.attributes() {
        let a = a.map_err(|err| malformed(format!("bad attribute: {err}")))?;
        if a.key.as_ref() == key.as_bytes() {
            let v = a.unescape_value().map_err(|err| malformed(format!("bad attribute `{key}`: {err}")))?;
            return Ok(Some(v.into_owned()));
        }
    }
    Ok(None)
}

fn required(e: &BytesStart<'_>, key: &str) -> Result<String> {
    let element = String::from_utf8_lossy(e.name().as_ref()).into_owned();
    attribute(e, key)?.ok_or_else(|| malformed(format!("<{element}> without `{key}`")))
}

fn escape(s: &str) -> String {
    quick_xml::escape::escape(s).into_owned()
}

impl Srdf {
    /// Parses SRDF text with the default [`XmlLimits`]. Groups, group states, disabled
    /// collisions, virtual joints, passive joints and end effectors are read; other elements
    /// are ignored and listed in [`Srdf::ignored`].
    ///
    /// # Errors
    /// [`CoreError::LimitExceeded`] for a document beyond the limits;
    /// [`CoreError::MalformedSrdf`] for XML errors, a root other than `<robot>`, missing
    /// attributes or a non-finite group-state value.
    pub fn parse(text: &str) -> Result<Self> {
        Self::parse_with_limits(text, &XmlLimits::default())
    }

    /// As [`Srdf::parse`], with explicit limits.
    ///
    /// # Errors
    /// As [`Srdf::parse`].
    pub fn parse_with_limits(text: &str, limits: &XmlLimits) -> Result<Self> {
        crate::urdf::check_xml(text.as_bytes(), limits, "srdf", |reason| CoreError::MalformedSrdf { reason })?;
        let mut reader = Reader::from_str(text);
        let mut srdf = Srdf::default();
        let mut depth = 0usize;
        let mut saw_root = false;
        // The open <group> or <group_state> (index into the lists) at depth 2.
        let (mut group, mut state): (Option<usize>, Option<usize>) = (None, None);
        loop {
            let event = reader.read_event().map_err(|e| malformed(format!("xml: {e}")))?;
            let (e, empty) = match &event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(_) => {
                    if depth == 2 {
                        (group, state) = (None, None);
                    }
                    depth = depth.saturating_sub(1);
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let name = e.name();
            let tag = name.as_ref();
            match depth {
                0 => {
                    if tag != b"robot" {
                        return Err(malformed(format!("root element <{}>, not <robot>", String::from_utf8_lossy(tag))));
                    }
                    saw_root = true;
                    srdf.robot = attribute(e, "name")?.unwrap_or_default();
                }
                1 => match tag {
                    b"group" => {
                        srdf.groups.push(SrdfGroup { name: required(e, "name")?, ..SrdfGroup::default() });
                        group = Some(srdf.groups.len() - 1);
                    }
                    b"group_state" => {
                        srdf.group_states.push(GroupState {
                            name: required(e, "name")?,
                            group: required(e, "group")?,
                            joints: Vec::new(),
                        });
                        state = Some(srdf.group_states.len() - 1);
                    }
                    b"disable_collisions" => srdf.disabled_collisions.push(DisabledCollision {
                        link1: required(e, "link1")?,
                        link2: required(e, "link2")?,
                        reason: attribute(e, "reason")?.unwrap_or_default(),
                    }),
                    b"virtual_joint" => srdf.virtual_joints.push(VirtualJoint {
                        name: required(e, "name")?,
                        kind: required(e, "type")?,
                        parent_frame: required(e, "parent_frame")?,
                        child_link: required(e, "child_link")?,
                    }),
                    b"passive_joint" => srdf.passive_joints.push(required(e, "name")?),
                    b"end_effector" => srdf.end_effectors.push(EndEffector {
                        name: required(e, "name")?,
                        group: required(e, "group")?,
                        parent_link: required(e, "parent_link")?,
                        parent_group: attribute(e, "parent_group")?,
                    }),
                    // Known to srdfdom but not modelled here: no note.
                    b"disable_default_collisions" | b"enable_collisions" | b"link_sphere_approximation" => {}
                    other => srdf.ignored.push(format!("<{}> at top level", String::from_utf8_lossy(other))),
                },
                2 => {
                    if let Some(g) = group {
                        let g = &mut srdf.groups[g];
                        match tag {
                            b"joint" => g.joints.push(required(e, "name")?),
                            b"link" => g.links.push(required(e, "name")?),
                            b"group" => g.subgroups.push(required(e, "name")?),
                            b"chain" => g.chains.push((required(e, "base_link")?, required(e, "tip_link")?)),
                            other => srdf.ignored.push(format!(
                                "<{}> inside group `{}`",
                                String::from_utf8_lossy(other),
                                g.name
                            )),
                        }
                    } else if let Some(s) = state {
                        if tag == b"joint" {
                            let joint = required(e, "name")?;
                            let raw = required(e, "value")?;
                            // Multi-DoF joints list several values; ours have one.
                            let value: f64 = raw.trim().parse().map_err(|_| {
                                malformed(format!(
                                    "group state `{}`: joint `{joint}` value {raw:?}",
                                    srdf.group_states[s].name
                                ))
                            })?;
                            if !value.is_finite() {
                                return Err(malformed(format!("group state value of `{joint}` is not finite")));
                            }
                            srdf.group_states[s].joints.push((joint, value));
                        }
                    }
                }
                _ => {}
            }
            if !empty {
                depth += 1;
            }
        }
        if !saw_root {
            return Err(malformed("no <robot> element"));
        }
        Ok(srdf)
    }

    /// Reads and parses an SRDF file.
    ///
    /// # Errors
    /// [`CoreError::Io`] if the file cannot be read; as [`Srdf::parse`].
    pub fn load_file(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let text =
            std::fs::read_to_string(path).map_err(|source| CoreError::Io { path: path.to_path_buf(), source })?;
        Self::parse(&text)
    }

    /// The SRDF of a robot: its joint groups and every allowed collision pair (reason
    /// `Adjacent` for links joined by a joint, `User` otherwise), in a deterministic order.
    pub fn from_robot(robot: &Robot) -> Self {
        let groups = robot
            .groups()
            .iter()
            .map(|g| SrdfGroup { name: g.name().to_string(), joints: g.joint_names().to_vec(), ..SrdfGroup::default() })
            .collect();
        // Joined by a joint: one link is the other's parent.
        let adjacent = |a: LinkId, b: LinkId| {
            [(a, b), (b, a)]
                .into_iter()
                .any(|(child, parent)| robot.parent_joint(child).is_some_and(|j| robot.joint(j).parent == parent))
        };
        let mut pairs: Vec<(LinkId, LinkId)> = robot.allowed_collision_pairs().collect();
        pairs.sort();
        let disabled_collisions = pairs
            .into_iter()
            .map(|(a, b)| DisabledCollision {
                link1: robot.links()[a.0].name.clone(),
                link2: robot.links()[b.0].name.clone(),
                reason: if adjacent(a, b) { "Adjacent" } else { "User" }.to_string(),
            })
            .collect();
        Self { robot: robot.name().to_string(), groups, disabled_collisions, ..Self::default() }
    }

    /// The document as SRDF text.
    pub fn to_xml(&self) -> String {
        let mut out = String::from("<?xml version=\"1.0\"?>\n");
        let _ = writeln!(out, "<robot name=\"{}\">", escape(&self.robot));
        for g in &self.groups {
            let _ = writeln!(out, "  <group name=\"{}\">", escape(&g.name));
            for j in &g.joints {
                let _ = writeln!(out, "    <joint name=\"{}\"/>", escape(j));
            }
            for l in &g.links {
                let _ = writeln!(out, "    <link name=\"{}\"/>", escape(l));
            }
            for (base, tip) in &g.chains {
                let _ = writeln!(out, "    <chain base_link=\"{}\" tip_link=\"{}\"/>", escape(base), escape(tip));
            }
            for s in &g.subgroups {
                let _ = writeln!(out, "    <group name=\"{}\"/>", escape(s));
            }
            out.push_str("  </group>\n");
        }
        for s in &self.group_states {
            let _ = writeln!(out, "  <group_state name=\"{}\" group=\"{}\">", escape(&s.name), escape(&s.group));
            for (j, v) in &s.joints {
                let _ = writeln!(out, "    <joint name=\"{}\" value=\"{v:?}\"/>", escape(j));
            }
            out.push_str("  </group_state>\n");
        }
        for d in &self.disabled_collisions {
            let _ = writeln!(
                out,
                "  <disable_collisions link1=\"{}\" link2=\"{}\" reason=\"{}\"/>",
                escape(&d.link1),
                escape(&d.link2),
                escape(&d.reason)
            );
        }
        out.push_str("</robot>\n");
        out
    }

    /// The degrees of freedom of group `name` as joint names, members resolved as in the
    /// [module docs](self), duplicates removed, in member order.
    ///
    /// # Errors
    /// [`CoreError::MalformedSrdf`] for an unknown or cyclic subgroup or a chain whose tip
    /// does not descend from its base; [`CoreError::UnknownJoint`] / [`CoreError::UnknownLink`]
    /// for names the robot does not have.
    pub fn group_joints(&self, robot: &Robot, name: &str) -> Result<Vec<String>> {
        let resolved = resolve::Resolver::new(self, robot).resolve(name)?;
        Ok(resolved.joints.iter().map(|&j| robot.joints()[j].name.clone()).collect())
    }

    /// Adds the groups to `robot` (replacing groups of the same name) and allows the
    /// disabled collision pairs. Nothing is changed if any group or pair is invalid.
    ///
    /// # Errors
    /// As [`Srdf::group_joints`]; [`CoreError::UnknownLink`] for a pair naming an unknown link;
    /// [`CoreError::LimitExceeded`] for more than [`MAX_GROUPS`] groups.
    pub fn apply(&self, robot: &mut Robot) -> Result<SrdfReport> {
        if self.groups.len() > MAX_GROUPS {
            return Err(CoreError::LimitExceeded {
                document: "srdf",
                what: "group count",
                limit: MAX_GROUPS,
                actual: self.groups.len(),
            });
        }
        let mut report = SrdfReport::default();
        let mut resolved = Vec::new();
        let mut resolver = resolve::Resolver::new(self, robot);
        for g in &self.groups {
            let r = resolver.resolve(&g.name)?;
            report.ignored.extend(
                r.virtual_joints.iter().map(|j| format!("virtual joint `{j}` in group `{}` (not modelled)", g.name)),
            );
            let joints: Vec<String> = r.joints.iter().map(|&j| robot.joints()[j].name.clone()).collect();
            if joints.is_empty() {
                report.skipped_groups.push(g.name.clone());
            } else {
                resolved.push((g.name.clone(), joints));
            }
        }
        for d in &self.disabled_collisions {
            robot.link_id(&d.link1)?;
            robot.link_id(&d.link2)?;
        }
        let mut updated = robot.clone();
        for (name, joints) in resolved {
            let names: Vec<&str> = joints.iter().map(String::as_str).collect();
            updated.add_group(&name, &names)?;
            report.groups.push(name);
        }
        for d in &self.disabled_collisions {
            updated.allow_collision(&d.link1, &d.link2)?;
            report.allowed_pairs += 1;
        }
        *robot = updated;
        Ok(report)
    }
}

/// Writes `<dir>/<robot name>.srdf` ([`Srdf::from_robot`]) atomically and returns its path.
///
/// # Errors
/// [`CoreError::Io`] if the directory or file cannot be written.
pub fn export(robot: &Robot, dir: &Path) -> Result<PathBuf> {
    let path = dir.join(format!("{}.srdf", robot.name()));
    crate::urdf::write_atomically(&path, Srdf::from_robot(robot).to_xml().as_bytes())?;
    Ok(path)
}
