//! `nav_msgs/Path` and Nav2 waypoint-follower goals as YAML, written as `ros2 topic pub` and
//! `ros2 action send_goal` take a message (a block mapping; the leading comment says how).

use super::{Pose2, RouteOut, WAYPOINT_TOLERANCE_M, num, poses, thin::waypoint_indices};
use crate::map::frame::MapFrame;
use std::fmt::Write;

/// The route as a `nav_msgs/msg/Path`, one pose per cell, each facing along the path.
pub fn nav_path(frame: &MapFrame, route: &RouteOut) -> String {
    let mut out = format!(
        "# nav_msgs/msg/Path: m2rc route on {}, {} poses, {} m, frame `{}`\n\
         # ros2 topic pub --once /plan nav_msgs/msg/Path \"$(cat this.yaml)\"\n",
        route.map_id,
        route.cells.len(),
        num(route.length_m, 2),
        frame.frame_id
    );
    header(&mut out, "", &frame.frame_id);
    out.push_str("poses:\n");
    for p in poses(frame, &route.cells) {
        pose_stamped(&mut out, &frame.frame_id, &p, None);
    }
    out
}

/// The route thinned to waypoints (the start, every stage goal, every turn beyond
/// [`WAYPOINT_TOLERANCE_M`]) as the goal of Nav2's `FollowWaypoints` action.
pub fn waypoints(frame: &MapFrame, route: &RouteOut) -> String {
    let ends: Vec<usize> = route.stages.iter().map(|s| s.end_index).collect();
    let keep = waypoint_indices(&route.cells, &ends, WAYPOINT_TOLERANCE_M / frame.resolution);
    let kept: Vec<_> = keep.iter().map(|&i| route.cells[i]).collect();
    let ps = poses(frame, &kept);
    let mut out = format!(
        "# nav2_msgs/action/FollowWaypoints goal: m2rc route on {}, {} waypoints of {} cells \
         (stage goals and turns beyond {} m), frame `{}`\n\
         # ros2 action send_goal /follow_waypoints nav2_msgs/action/FollowWaypoints \"$(cat this.yaml)\"\n",
        route.map_id,
        kept.len(),
        route.cells.len(),
        num(WAYPOINT_TOLERANCE_M, 2),
        frame.frame_id
    );
    out.push_str("poses:\n");
    for (k, p) in keep.iter().zip(&ps) {
        let stage = route
            .stages
            .iter()
            .enumerate()
            .find(|(_, s)| s.end_index.min(route.cells.len().saturating_sub(1)) == *k);
        let note = match stage {
            Some((i, s)) => format!("stage {}: {} ({})", i + 1, s.name, s.target),
            None if *k == 0 => "start".to_string(),
            None => "turn".to_string(),
        };
        pose_stamped(&mut out, &frame.frame_id, p, Some(&note));
    }
    out
}

fn header(out: &mut String, indent: &str, frame_id: &str) {
    let _ = write!(
        out,
        "{indent}header:\n{indent}  stamp: {{sec: 0, nanosec: 0}}\n{indent}  frame_id: {frame_id}\n"
    );
}

fn pose_stamped(out: &mut String, frame_id: &str, p: &Pose2, note: Option<&str>) {
    if let Some(n) = note {
        let _ = writeln!(out, "  # {n}");
    }
    let _ = write!(
        out,
        "  - header:\n      stamp: {{sec: 0, nanosec: 0}}\n      frame_id: {frame_id}\n"
    );
    let [qx, qy, qz, qw] = p.quaternion();
    let _ = write!(
        out,
        "    pose:\n      position: {{x: {}, y: {}, z: 0.0}}\n      orientation: {{x: {}, y: {}, z: {}, w: {}}}\n",
        num(p.x, 4),
        num(p.y, 4),
        num(qx, 6),
        num(qy, 6),
        num(qz, 6),
        num(qw, 6)
    );
}
