//! Group resolution: iterative (no recursion, so subgroup chains of any length cannot
//! overflow the stack) and memoised through a name index (each group is expanded once, so
//! groups sharing subgroups cost time linear in the document, not exponential).

use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use super::{malformed, Srdf};
use crate::error::Result;
use crate::model::{JointKind, Robot};

/// A group's degrees of freedom (joint indices, member order, no duplicates) and the virtual
/// joints it names.
#[derive(Debug, Default)]
pub(super) struct Resolved {
    pub(super) joints: Vec<usize>,
    pub(super) virtual_joints: Vec<String>,
}

/// Resolves groups of one document against one robot, remembering every group it expanded.
pub(super) struct Resolver<'a> {
    srdf: &'a Srdf,
    robot: &'a Robot,
    /// Group name → index of its first definition.
    index: HashMap<&'a str, usize>,
    virtual_joints: HashSet<&'a str>,
    passive: HashSet<&'a str>,
    memo: Vec<Option<Rc<Resolved>>>,
}

impl<'a> Resolver<'a> {
    pub(super) fn new(srdf: &'a Srdf, robot: &'a Robot) -> Self {
        let mut index = HashMap::with_capacity(srdf.groups.len());
        for (i, g) in srdf.groups.iter().enumerate() {
            index.entry(g.name.as_str()).or_insert(i);
        }
        Self {
            srdf,
            robot,
            index,
            virtual_joints: srdf.virtual_joints.iter().map(|v| v.name.as_str()).collect(),
            passive: srdf.passive_joints.iter().map(String::as_str).collect(),
            memo: vec![None; srdf.groups.len()],
        }
    }

    fn group_index(&self, name: &str) -> Result<usize> {
        self.index.get(name).copied().ok_or_else(|| malformed(format!("unknown group `{name}`")))
    }

    /// Resolves group `name` and, on the way, every group it includes.
    pub(super) fn resolve(&mut self, name: &str) -> Result<Rc<Resolved>> {
        let root = self.group_index(name)?;
        if let Some(done) = &self.memo[root] {
            return Ok(done.clone());
        }
        let mut open = vec![false; self.srdf.groups.len()];
        // (group, next subgroup to visit)
        let mut stack = vec![(root, 0usize)];
        open[root] = true;
        while let Some(&mut (g, ref mut next)) = stack.last_mut() {
            let subgroups = &self.srdf.groups[g].subgroups;
            if let Some(sub) = subgroups.get(*next) {
                *next += 1;
                let c = self.group_index(sub)?;
                if self.memo[c].is_some() {
                    continue;
                }
                if open[c] {
                    let path: Vec<&str> = stack.iter().map(|&(i, _)| self.srdf.groups[i].name.as_str()).collect();
                    return Err(malformed(format!("group `{sub}` contains itself (via {})", path.join(" -> "))));
                }
                open[c] = true;
                stack.push((c, 0));
            } else {
                stack.pop();
                open[g] = false;
                let resolved = self.expand(g)?;
                self.memo[g] = Some(Rc::new(resolved));
            }
        }
        self.memo[root].clone().ok_or_else(|| malformed(format!("group `{name}` could not be resolved")))
    }

    /// Group `g`'s own members, then its (already resolved) subgroups.
    fn expand(&self, g: usize) -> Result<Resolved> {
        let group = &self.srdf.groups[g];
        let robot = self.robot;
        let mut out = Resolved::default();
        let mut seen = HashSet::new();
        let mut push = |out: &mut Resolved, joint: usize| {
            let j = &robot.joints()[joint];
            let moves =
                !matches!(j.kind, JointKind::Fixed) && j.mimic.is_none() && !self.passive.contains(j.name.as_str());
            if moves && seen.insert(joint) {
                out.joints.push(joint);
            }
        };
        for j in &group.joints {
            match robot.joint_id(j) {
                Ok(id) => push(&mut out, id.0),
                Err(_) if self.virtual_joints.contains(j.as_str()) => {
                    if !out.virtual_joints.contains(j) {
                        out.virtual_joints.push(j.clone());
                    }
                }
                Err(e) => return Err(e),
            }
        }
        for l in &group.links {
            if let Some(j) = robot.parent_joint(robot.link_id(l)?) {
                push(&mut out, j.0);
            }
        }
        for (base, tip) in &group.chains {
            let (base_id, tip_id) = (robot.link_id(base)?, robot.link_id(tip)?);
            let mut chain = Vec::new();
            let mut link = tip_id;
            while link != base_id {
                let j = robot.parent_joint(link).ok_or_else(|| {
                    malformed(format!("group `{}`: chain tip `{tip}` does not descend from base `{base}`", group.name))
                })?;
                chain.push(j.0);
                link = robot.joints()[j.0].parent;
            }
            for j in chain.into_iter().rev() {
                push(&mut out, j);
            }
        }
        for sub in &group.subgroups {
            let c = self.group_index(sub)?;
            let Some(child) = &self.memo[c] else {
                return Err(malformed(format!("group `{sub}` could not be resolved")));
            };
            for &j in &child.joints {
                push(&mut out, j);
            }
            for v in &child.virtual_joints {
                if !out.virtual_joints.contains(v) {
                    out.virtual_joints.push(v.clone());
                }
            }
        }
        Ok(out)
    }
}
