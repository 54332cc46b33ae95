//! The `navigate_to_pose` action (`nav2_msgs/action/NavigateToPose`) without DDS: goals,
//! cancels, result requests and feedback as [`Navigate`]'s state machine over a [`Bridge`];
//! `main.rs` moves its inputs and outputs through ros2-client's synchronous `ActionServer`.
//!
//! As Nav2's navigator does:
//!
//! - one goal runs at a time; a new goal (or a pose on `/goal_pose`) replaces it, and the
//!   replaced goal is **aborted** with its result (`error_msg` says it was preempted);
//! - a goal whose position is not finite is **rejected**; one outside `/map` or in an occupied
//!   or unknown cell is accepted and at once **aborted** with [`code::GOAL_OUTSIDE_MAP`] or
//!   [`code::GOAL_OCCUPIED`], and one the navigator cannot be built for with
//!   [`code::NO_VALID_PATH`] (Nav2's planner codes, the ones its navigator passes on);
//! - a cancel stops the robot (the bridge forgets the goal, so the next command is zero) and
//!   the goal ends **canceled**;
//! - arrival (within `goal_tolerance`; on a `diff` base with `use_goal_orientation`, at the
//!   goal's yaw after the turn in place, [`Bridge::set_goal`]) ends the goal **succeeded**;
//! - a goal whose quaternion is not a rotation is **rejected** when its orientation is used;
//! - stale data, a refused scan or command stop the robot but keep the goal running (the
//!   bridge resumes when the data is fresh again), until the robot has not moved
//!   `required_movement_radius` for `movement_time_allowance` (Nav2's progress checker, for
//!   whatever reason it stands or crawls): then the goal is **aborted** with
//!   [`code::FAILED_TO_MAKE_PROGRESS`] and the robot stopped.
//!
//! Feedback goes out with every command while a goal runs: the robot's pose, the straight-line
//! distance to the goal, the time since acceptance and that distance over the commanded speed.

use std::time::Instant;

use byteorder::LittleEndian;
use ros2_client::action::{CancelGoalRequest, GoalId, GoalInfo, GoalStatusEnum};
use ros2_client::action_msgs::{
    CancelGoalResponse, CancelGoalResponseEnum, GoalStatus, GoalStatusArray,
};
use ros2_client::builtin_interfaces::Time as RosTime;

use crate::bridge::{Bridge, GoalCheck, Step, Stop};
use crate::msgs::{
    Duration, Header, NavigateToPoseFeedback, NavigateToPoseGoal, NavigateToPoseResult, Point,
    Pose, PoseStamped, Quaternion, Time,
};

/// The action's default name (Nav2's).
pub const ACTION_NAME: &str = "navigate_to_pose";

/// Result error codes. Jazzy's `NavigateToPose.action` defines only `NONE`; Nav2's navigator
/// reports its planner's codes (`nav2_msgs/action/ComputePathToPose`), and so does this node.
pub mod code {
    /// No error (also for a canceled or preempted goal: `error_msg` says which).
    pub const NONE: u16 = 0;
    /// The goal is outside `/map` (`ComputePathToPose.GOAL_OUTSIDE_MAP`).
    pub const GOAL_OUTSIDE_MAP: u16 = 204;
    /// The goal is in an occupied or unknown cell of `/map`
    /// (`ComputePathToPose.GOAL_OCCUPIED`).
    pub const GOAL_OCCUPIED: u16 = 206;
    /// No navigator could be built for the goal, e.g. the robot or the goal is not in the free
    /// space the robot's radius leaves (`ComputePathToPose.NO_VALID_PATH`).
    pub const NO_VALID_PATH: u16 = 208;
    /// The robot did not move `required_movement_radius` in `movement_time_allowance`
    /// (`FollowPath.FAILED_TO_MAKE_PROGRESS`, Nav2's controller's code for its progress
    /// checker).
    pub const FAILED_TO_MAKE_PROGRESS: u16 = 105;
}

/// How many finished goals are kept (their results can still be asked for, and they stay in
/// the status array).
pub const KEPT_FINISHED: usize = 16;

/// The goal info of a cancel request (ros2-client keeps the field private: the request is
/// re-read through its CDR bytes, which are exactly a `GoalInfo`'s); `None` if that fails.
#[must_use]
pub fn cancel_goal_info(request: &CancelGoalRequest) -> Option<GoalInfo> {
    let bytes = cdr_encoding::to_vec::<_, LittleEndian>(request).ok()?;
    cdr_encoding::from_bytes::<GoalInfo, LittleEndian>(&bytes)
        .ok()
        .map(|(info, _)| info)
}

/// A result to send: to the request `to`, the goal's end status and its result.
#[derive(Clone, Debug, PartialEq)]
pub struct Reply<Q> {
    /// The result request answered.
    pub to: Q,
    /// The goal's status (`Unknown` for a goal never seen).
    pub status: GoalStatusEnum,
    /// The result.
    pub result: NavigateToPoseResult,
}

/// One goal.
#[derive(Clone, Debug)]
struct Record {
    id: GoalId,
    /// When it was accepted.
    stamp: RosTime,
    started: Instant,
    status: GoalStatusEnum,
    result: NavigateToPoseResult,
}

fn terminal(s: GoalStatusEnum) -> bool {
    matches!(
        s,
        GoalStatusEnum::Succeeded | GoalStatusEnum::Canceled | GoalStatusEnum::Aborted
    )
}

/// The action server's state; `Q` identifies a result request (ros2-client's `RmwRequestId`
/// in the node, anything in the tests).
pub struct Navigate<Q> {
    /// Oldest first.
    goals: Vec<Record>,
    active: Option<GoalId>,
    /// Result requests of goals that have not ended.
    waiting: Vec<(GoalId, Q)>,
    replies: Vec<Reply<Q>>,
    status_changed: bool,
    log: Vec<(log::Level, String)>,
}

impl<Q> Default for Navigate<Q> {
    fn default() -> Self {
        Self::new()
    }
}

impl<Q> Navigate<Q> {
    /// No goal yet.
    #[must_use]
    pub fn new() -> Self {
        Self {
            goals: Vec::new(),
            active: None,
            waiting: Vec::new(),
            replies: Vec::new(),
            status_changed: false,
            log: Vec::new(),
        }
    }

    /// The running goal.
    #[must_use]
    pub fn active(&self) -> Option<GoalId> {
        self.active
    }

    /// A goal's status, `None` if it is not known (never seen, or forgotten).
    #[must_use]
    pub fn status(&self, id: GoalId) -> Option<GoalStatusEnum> {
        self.goals.iter().find(|r| r.id == id).map(|r| r.status)
    }

    /// A finished goal's result.
    #[must_use]
    pub fn result(&self, id: GoalId) -> Option<&NavigateToPoseResult> {
        self.goals
            .iter()
            .find(|r| r.id == id && terminal(r.status))
            .map(|r| &r.result)
    }

    /// The results to send now.
    pub fn take_replies(&mut self) -> Vec<Reply<Q>> {
        std::mem::take(&mut self.replies)
    }

    /// The log lines since the last call.
    pub fn drain_log(&mut self) -> Vec<(log::Level, String)> {
        std::mem::take(&mut self.log)
    }

    /// The status array of every known goal, once after each change (`None` when nothing
    /// changed since the last call).
    pub fn take_status(&mut self) -> Option<GoalStatusArray> {
        if !std::mem::take(&mut self.status_changed) {
            return None;
        }
        Some(GoalStatusArray {
            status_list: self
                .goals
                .iter()
                .map(|r| GoalStatus {
                    goal_info: GoalInfo {
                        goal_id: r.id,
                        stamp: r.stamp,
                    },
                    status: r.status,
                })
                .collect(),
        })
    }

    /// Ends goal `id` (if it is running) with `status` and a result; answers the result
    /// requests waiting for it.
    fn finish(&mut self, id: GoalId, status: GoalStatusEnum, error_code: u16, error_msg: String)
    where
        Q: Clone,
    {
        let Some(r) = self
            .goals
            .iter_mut()
            .find(|r| r.id == id && !terminal(r.status))
        else {
            return;
        };
        r.status = status;
        r.result = NavigateToPoseResult {
            error_code,
            error_msg,
        };
        let result = r.result.clone();
        if self.active == Some(id) {
            self.active = None;
        }
        let level = if status == GoalStatusEnum::Aborted {
            log::Level::Warn
        } else {
            log::Level::Info
        };
        let why = if result.error_msg.is_empty() {
            String::new()
        } else {
            format!(": {} (code {})", result.error_msg, result.error_code)
        };
        self.log.push((
            level,
            format!("navigate_to_pose: goal {id:?} {status:?}{why}"),
        ));
        let (now, later): (Vec<_>, Vec<_>) = std::mem::take(&mut self.waiting)
            .into_iter()
            .partition(|(g, _)| *g == id);
        self.waiting = later;
        self.replies.extend(now.into_iter().map(|(_, to)| Reply {
            to,
            status,
            result: result.clone(),
        }));
        self.status_changed = true;
    }

    /// Forgets the oldest finished goals beyond [`KEPT_FINISHED`].
    fn trim(&mut self) {
        let finished = self.goals.iter().filter(|r| terminal(r.status)).count();
        let mut drop = finished.saturating_sub(KEPT_FINISHED);
        self.goals.retain(|r| {
            if drop > 0 && terminal(r.status) {
                drop -= 1;
                false
            } else {
                true
            }
        });
    }

    /// A goal request: whether it is accepted. An accepted goal replaces the running one
    /// (aborted, "preempted") and runs at once, unless it is not in free space on `/map`
    /// (then it is aborted with its code at once; the robot stops).
    pub fn send_goal(
        &mut self,
        id: GoalId,
        goal: &NavigateToPoseGoal,
        bridge: &mut Bridge,
        now: Instant,
        stamp: RosTime,
    ) -> bool
    where
        Q: Clone,
    {
        if self.goals.iter().any(|r| r.id == id) {
            self.log.push((
                log::Level::Warn,
                format!("navigate_to_pose: goal {id:?} rejected: its id is taken"),
            ));
            return false;
        }
        let g = match bridge.set_goal(&goal.pose, now) {
            Ok(g) => g,
            Err(e) => {
                self.log.push((
                    log::Level::Warn,
                    format!("navigate_to_pose: goal {id:?} rejected: {e}"),
                ));
                return false;
            }
        };
        if let Some(old) = self.active {
            self.finish(
                old,
                GoalStatusEnum::Aborted,
                code::NONE,
                "preempted by a new goal".into(),
            );
        }
        self.goals.push(Record {
            id,
            stamp,
            started: now,
            status: GoalStatusEnum::Executing,
            result: NavigateToPoseResult::default(),
        });
        self.active = Some(id);
        self.status_changed = true;
        self.log.push((
            log::Level::Info,
            format!(
                "navigate_to_pose: goal {id:?} accepted: ({:.3}, {:.3})",
                g.x, g.y
            ),
        ));
        let refused = match bridge.goal_check(g) {
            GoalCheck::Free | GoalCheck::Unchecked => None,
            GoalCheck::OutsideMap => Some((code::GOAL_OUTSIDE_MAP, "outside the map")),
            GoalCheck::Occupied => Some((code::GOAL_OCCUPIED, "in an occupied cell of the map")),
            GoalCheck::Unknown => Some((code::GOAL_OCCUPIED, "in an unknown cell of the map")),
        };
        if let Some((c, text)) = refused {
            bridge.clear_goal();
            self.finish(
                id,
                GoalStatusEnum::Aborted,
                c,
                format!("goal ({:.3}, {:.3}) is {text}", g.x, g.y),
            );
        }
        self.trim();
        true
    }

    /// A pose on `/goal_pose`: it replaces the running goal (aborted, "preempted"), as a new
    /// action goal would.
    pub fn goal_topic(&mut self, m: &PoseStamped, bridge: &mut Bridge, now: Instant)
    where
        Q: Clone,
    {
        if let Err(e) = bridge.set_goal(m, now) {
            self.log.push((log::Level::Warn, e.0));
            return;
        }
        if let Some(old) = self.active {
            self.finish(
                old,
                GoalStatusEnum::Aborted,
                code::NONE,
                "preempted by a goal on the goal topic".into(),
            );
        }
    }

    /// A cancel request (`action_msgs/srv/CancelGoal`'s policy: a zero id and a zero stamp
    /// cancel every goal, a stamp every goal accepted at or before it, an id that goal). The
    /// running goal among them stops the robot and ends canceled.
    pub fn cancel(&mut self, info: &GoalInfo, bridge: &mut Bridge) -> CancelGoalResponse
    where
        Q: Clone,
    {
        let zero_id = info.goal_id == GoalId::ZERO;
        let zero_stamp = info.stamp.to_nanos() == 0;
        let before = info.stamp.to_nanos();
        let chosen: Vec<GoalInfo> = self
            .goals
            .iter()
            .filter(|r| !terminal(r.status))
            .filter(|r| {
                (zero_id && zero_stamp)
                    || (!zero_id && r.id == info.goal_id)
                    || (!zero_stamp && r.stamp.to_nanos() <= before)
            })
            .map(|r| GoalInfo {
                goal_id: r.id,
                stamp: r.stamp,
            })
            .collect();
        for g in &chosen {
            if self.active == Some(g.goal_id) {
                bridge.clear_goal();
            }
            self.finish(
                g.goal_id,
                GoalStatusEnum::Canceled,
                code::NONE,
                "canceled".into(),
            );
        }
        let return_code = if !chosen.is_empty() || zero_id {
            CancelGoalResponseEnum::None
        } else if self.goals.iter().any(|r| r.id == info.goal_id) {
            CancelGoalResponseEnum::GoalTerminated
        } else {
            CancelGoalResponseEnum::UnknownGoal
        };
        if chosen.is_empty() {
            self.log.push((
                log::Level::Info,
                format!(
                    "navigate_to_pose: cancel of {:?}: nothing to cancel ({return_code:?})",
                    info.goal_id
                ),
            ));
        }
        CancelGoalResponse {
            return_code,
            goals_canceling: chosen,
        }
    }

    /// A result request: answered at once for a finished goal (and, with status `Unknown`,
    /// for a goal never seen), else when the goal ends.
    pub fn result_request(&mut self, id: GoalId, to: Q) {
        match self.goals.iter().find(|r| r.id == id) {
            Some(r) if terminal(r.status) => self.replies.push(Reply {
                to,
                status: r.status,
                result: r.result.clone(),
            }),
            Some(_) => self.waiting.push((id, to)),
            None => self.replies.push(Reply {
                to,
                status: GoalStatusEnum::Unknown,
                result: NavigateToPoseResult {
                    error_code: code::NONE,
                    error_msg: "unknown goal".into(),
                },
            }),
        }
    }

    /// After a control step: arrival ends the running goal succeeded, a navigator that cannot
    /// be built aborts it ([`code::NO_VALID_PATH`], the robot stops); otherwise the feedback to
    /// publish for it (`stamp`: its header's).
    pub fn after_step(
        &mut self,
        step: &Step,
        bridge: &mut Bridge,
        now: Instant,
        stamp: Time,
    ) -> Option<(GoalId, NavigateToPoseFeedback)>
    where
        Q: Clone,
    {
        let id = self.active?;
        match &step.stop {
            Some(Stop::Arrived) => {
                self.finish(id, GoalStatusEnum::Succeeded, code::NONE, String::new());
                self.trim();
                return None;
            }
            Some(Stop::NoNavigator(e)) => {
                bridge.clear_goal();
                self.finish(id, GoalStatusEnum::Aborted, code::NO_VALID_PATH, e.clone());
                self.trim();
                return None;
            }
            Some(Stop::NoProgress(e)) => {
                // The bridge has cleared the goal already: the robot stands.
                self.finish(
                    id,
                    GoalStatusEnum::Aborted,
                    code::FAILED_TO_MAKE_PROGRESS,
                    format!("failed to make progress: {e}"),
                );
                self.trim();
                return None;
            }
            _ => {}
        }
        let started = self.goals.iter().find(|r| r.id == id)?.started;
        let goal = bridge.goal()?;
        let pose = bridge.pose(now);
        let distance = pose.map_or(0.0, |p| (goal - harmonav::Vector2::new(p.x, p.y)).norm());
        let speed = step.twist.linear.x.hypot(step.twist.linear.y);
        let eta = if speed > 1e-3 { distance / speed } else { 0.0 };
        let current_pose = PoseStamped {
            header: Header {
                stamp,
                frame_id: bridge.params().global_frame.clone(),
            },
            pose: pose.map_or_else(Pose::default, |p| Pose {
                position: Point {
                    x: p.x,
                    y: p.y,
                    z: 0.0,
                },
                orientation: Quaternion::from_yaw(p.yaw),
            }),
        };
        #[allow(clippy::cast_possible_truncation)]
        let distance_remaining = distance as f32;
        Some((
            id,
            NavigateToPoseFeedback {
                current_pose,
                navigation_time: Duration::from_seconds(
                    now.saturating_duration_since(started).as_secs_f64(),
                ),
                estimated_time_remaining: Duration::from_seconds(eta),
                number_of_recoveries: 0,
                distance_remaining,
            },
        ))
    }

    /// Shutting down: the running goal is aborted (its waiting result requests answered).
    pub fn shutdown(&mut self)
    where
        Q: Clone,
    {
        if let Some(id) = self.active {
            self.finish(
                id,
                GoalStatusEnum::Aborted,
                code::NONE,
                "the node is shutting down".into(),
            );
        }
    }
}
