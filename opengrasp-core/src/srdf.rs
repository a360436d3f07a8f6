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
//! of another group. Fixed and mimic joints are dropped (they are not degrees of freedom);
//! a group left with no degree of freedom (e.g. an end-effector link group) is skipped and
//! listed in [`SrdfReport::skipped_groups`]. Unknown names are errors.
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
use crate::model::{JointKind, LinkId, Robot};

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
    /// Parses SRDF text. Elements other than groups, group states and disabled collisions
    /// (end effectors, virtual joints, passive joints, ...) are accepted and ignored.
    ///
    /// # Errors
    /// [`CoreError::MalformedSrdf`] for XML errors, a root other than `<robot>`, missing
    /// attributes, members outside a group, or a non-finite group-state value.
    pub fn parse(text: &str) -> Result<Self> {
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
                    _ => {}
                },
                2 => {
                    if let Some(g) = group {
                        let g = &mut srdf.groups[g];
                        match tag {
                            b"joint" => g.joints.push(required(e, "name")?),
                            b"link" => g.links.push(required(e, "name")?),
                            b"group" => g.subgroups.push(required(e, "name")?),
                            b"chain" => g.chains.push((required(e, "base_link")?, required(e, "tip_link")?)),
                            other => {
                                return Err(malformed(format!(
                                    "<{}> inside group `{}`",
                                    String::from_utf8_lossy(other),
                                    g.name
                                )))
                            }
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
        Self { robot: robot.name().to_string(), groups, group_states: Vec::new(), disabled_collisions }
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
        let mut out = Vec::new();
        self.collect_group(robot, name, &mut Vec::new(), &mut out)?;
        Ok(out)
    }

    fn collect_group(&self, robot: &Robot, name: &str, stack: &mut Vec<String>, out: &mut Vec<String>) -> Result<()> {
        if stack.iter().any(|s| s == name) {
            return Err(malformed(format!("group `{name}` contains itself (via {})", stack.join(" -> "))));
        }
        let group =
            self.groups.iter().find(|g| g.name == name).ok_or_else(|| malformed(format!("unknown group `{name}`")))?;
        stack.push(name.to_string());
        let mut push = |joint: usize| {
            let j = &robot.joints()[joint];
            let moves = !matches!(j.kind, JointKind::Fixed) && j.mimic.is_none();
            if moves && !out.contains(&j.name) {
                out.push(j.name.clone());
            }
        };
        for j in &group.joints {
            push(robot.joint_id(j)?.0);
        }
        for l in &group.links {
            if let Some(j) = robot.parent_joint(robot.link_id(l)?) {
                push(j.0);
            }
        }
        for (base, tip) in &group.chains {
            let (base_id, tip_id) = (robot.link_id(base)?, robot.link_id(tip)?);
            let mut chain = Vec::new();
            let mut link = tip_id;
            while link != base_id {
                let j = robot.parent_joint(link).ok_or_else(|| {
                    malformed(format!("group `{name}`: chain tip `{tip}` does not descend from base `{base}`"))
                })?;
                chain.push(j.0);
                link = robot.joints()[j.0].parent;
            }
            for j in chain.into_iter().rev() {
                push(j);
            }
        }
        for s in &group.subgroups {
            self.collect_group(robot, s, stack, out)?;
        }
        stack.pop();
        Ok(())
    }

    /// Adds the groups to `robot` (replacing groups of the same name) and allows the
    /// disabled collision pairs. Nothing is changed if any group or pair is invalid.
    ///
    /// # Errors
    /// As [`Srdf::group_joints`]; [`CoreError::UnknownLink`] for a pair naming an unknown link.
    pub fn apply(&self, robot: &mut Robot) -> Result<SrdfReport> {
        let mut report = SrdfReport::default();
        let mut resolved = Vec::new();
        for g in &self.groups {
            let joints = self.group_joints(robot, &g.name)?;
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
