//! `harmonav-ros2`: the DDS side of the node (crate docs: [`harmonav_ros2`]).
//!
//! One thread polls the subscriptions every millisecond (a scan is answered as soon as it is
//! taken; otherwise a command goes out every control period), so there is no executor and no
//! ros2-client `Spinner`: the spinner would subscribe `/clock` as
//! `builtin_interfaces/msg/Time`, a type no simulator publishes (the `/clock` trap), and this
//! node subscribes it as `rosgraph_msgs/msg/Clock` itself when `use_sim_time` is set.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant, SystemTime};

use ros2_client::action::{ActionServer, GetResultResponse, SendGoalResponse};
use ros2_client::builtin_interfaces::Time as RosTime;
use ros2_client::dds::rustdds::DomainParticipantBuilder;
use ros2_client::dds::{Context, Node, Publisher, Subscription};
use ros2_client::qos::{Durability, History, QosProfile, Reliability, WhenFull};
use ros2_client::request_id::RmwRequestId;
use ros2_client::{
    ActionTypeName, MessageTypeName, Name, NodeName, NodeOptions, ServiceMapping, action,
};
use serde::Serialize;

use harmonav_ros2::action::{Navigate, cancel_goal_info};
use harmonav_ros2::bridge::Bridge;
use harmonav_ros2::msgs::{
    Clock, Header, LaserScan, MarkerArray, NavigateToPoseFeedback, NavigateToPoseGoal,
    NavigateToPoseResult, OccupancyGrid, Odometry, PoseStamped, StringMsg, TFMessage, Time, Twist,
    TwistStamped,
};
use harmonav_ros2::params::{Cli, NODE_NAME, Params, ServiceWire, USAGE, parse_args};

/// A failure before the loop: the message and the exit code.
struct Fatal(String, i32);

impl<E: std::fmt::Display> From<E> for Fatal {
    fn from(e: E) -> Self {
        Fatal(e.to_string(), 1)
    }
}

/// stderr lines `[t s] LEVEL target: text`; RustDDS and ros2-client at `Error` only (RustDDS
/// warns for every datagram over 1 500 bytes, a large scan or map; ros2-client errors on an
/// early subscription count).
struct Logger {
    level: log::LevelFilter,
    start: Instant,
}

impl log::Log for Logger {
    fn enabled(&self, m: &log::Metadata) -> bool {
        let t = m.target();
        if t.starts_with("rustdds") || t.starts_with("ros2_client") {
            m.level() <= log::Level::Error
        } else {
            m.level() <= self.level
        }
    }

    fn log(&self, r: &log::Record) {
        if self.enabled(r.metadata()) {
            eprintln!(
                "[{:9.3}] {:5} {}",
                self.start.elapsed().as_secs_f64(),
                r.level(),
                r.args()
            );
        }
    }

    fn flush(&self) {}
}

/// The participant for `ROS_DOMAIN_ID` and the discovery-range variables (ros2-client reads
/// none of them).
fn participant() -> Result<Context, Fatal> {
    let var = |k: &str| std::env::var(k).ok().filter(|v| !v.trim().is_empty());
    let domain = match var("ROS_DOMAIN_ID") {
        None => 0,
        Some(v) => match v.trim().parse::<u16>() {
            // DDS's port formula overflows above 232 (ROS documents 0–101 and 215–232).
            Ok(d) if d <= 232 => d,
            _ => {
                return Err(Fatal(
                    format!("ROS_DOMAIN_ID={v:?}: expected an integer 0–232"),
                    2,
                ));
            }
        },
    };
    let mut builder = DomainParticipantBuilder::new(domain);
    let localhost_only = var("ROS_LOCALHOST_ONLY").is_some_and(|v| v.trim() == "1");
    let range = var("ROS_AUTOMATIC_DISCOVERY_RANGE").map(|v| v.trim().to_ascii_uppercase());
    match range.as_deref() {
        Some("LOCALHOST") => builder = builder.with_only_networks([[127u8, 0, 0, 1]]),
        Some("OFF") => {
            // RustDDS cannot switch discovery off; no interface and no same-host announcements
            // is the nearest it has.
            builder = builder
                .with_only_networks(std::iter::empty::<std::net::IpAddr>())
                .same_host_loopback(false);
        }
        Some("SUBNET" | "SYSTEM_DEFAULT") => {}
        None if localhost_only => builder = builder.with_only_networks([[127u8, 0, 0, 1]]),
        None => {}
        Some(other) => {
            return Err(Fatal(
                format!(
                    "ROS_AUTOMATIC_DISCOVERY_RANGE={other:?}: expected LOCALHOST, SUBNET, OFF or \
                     SYSTEM_DEFAULT"
                ),
                2,
            ));
        }
    }
    if let Some(peers) = var("ROS_STATIC_PEERS") {
        log::warn!("ROS_STATIC_PEERS={peers:?} is ignored: RustDDS has no static peer list");
    }
    log::info!(
        "DDS domain {domain}, discovery range {}",
        range.as_deref().unwrap_or(if localhost_only {
            "LOCALHOST (ROS_LOCALHOST_ONLY)"
        } else {
            "SUBNET"
        })
    );
    Ok(Context::from_domain_participant(builder.build()?)?)
}

/// `scan`, `/scan`, `harmonav/status` as a ROS name.
fn name(topic: &str) -> Result<Name, Fatal> {
    let full = if topic.starts_with('/') {
        topic.to_owned()
    } else {
        format!("/{topic}")
    };
    Name::parse(&full).map_err(|e| Fatal(format!("topic name {topic:?}: {e:?}"), 2))
}

fn qos(reliable: bool, transient: bool, depth: usize) -> QosProfile {
    QosProfile::subscription_default()
        .reliability(if reliable {
            Reliability::Reliable {
                when_full: WhenFull::DEFAULT,
            }
        } else {
            Reliability::BestEffort
        })
        .durability(if transient {
            Durability::TransientLocal
        } else {
            Durability::Volatile
        })
        .history(History::KeepLast { depth })
}

fn subscribe<M: 'static>(
    node: &mut Node,
    topic: &str,
    package: &str,
    ty: &str,
    q: QosProfile,
) -> Result<Subscription<M>, Fatal> {
    let t = node.create_topic(&name(topic)?, MessageTypeName::new(package, ty), &q)?;
    Ok(node.create_subscription::<M>(&t, Some(q))?)
}

fn advertise<M: Serialize>(
    node: &mut Node,
    topic: &str,
    package: &str,
    ty: &str,
    q: QosProfile,
) -> Result<Publisher<M>, Fatal> {
    let t = node.create_topic(&name(topic)?, MessageTypeName::new(package, ty), &q)?;
    Ok(node.create_publisher::<M>(&t, Some(q))?)
}

type NavServer = ActionServer<NavigateToPoseGoal, NavigateToPoseResult, NavigateToPoseFeedback>;

/// The `navigate_to_pose` action server with rcl's default QoS: reliable, volatile services
/// and feedback; a transient-local status (an action client asks for it).
fn action_server(node: &mut Node, p: &Params) -> Result<NavServer, Fatal> {
    let service = qos(true, false, 10);
    let qos = action::ActionServerQosPolicies {
        goal_service: service.clone(),
        result_service: service.clone(),
        cancel_service: service,
        feedback_publisher: qos(true, false, 10),
        status_publisher: qos(true, true, 1),
    };
    let mapping = match p.service_mapping {
        ServiceWire::Enhanced => ServiceMapping::Enhanced,
        ServiceWire::Cyclone => ServiceMapping::Cyclone,
    };
    Ok(node.create_action_server(
        mapping,
        &name(&p.action_name)?,
        &ActionTypeName::new("nav2_msgs", "NavigateToPose"),
        qos,
    )?)
}

/// Moves the action's requests into `nav` (goals and cancels act on the bridge at once) and
/// its replies out; at most 100 requests of each kind per call.
fn serve(server: &NavServer, nav: &mut Navigate<RmwRequestId>, bridge: &mut Bridge, now: Instant) {
    for _ in 0..100 {
        match server.receive_goal() {
            Ok(Some((req, goal))) => {
                let stamp = RosTime::now();
                let accepted = nav.send_goal(goal.goal_id, &goal.goal, bridge, now, stamp);
                if let Err(e) = server.send_goal_response(req, SendGoalResponse { accepted, stamp })
                {
                    log::error!("navigate_to_pose: goal response not sent: {e:?}");
                }
            }
            Ok(None) => break,
            Err(e) => log::warn!("navigate_to_pose: goal request dropped: {e:?}"),
        }
    }
    for _ in 0..100 {
        match server.receive_cancel_request() {
            Ok(Some((req, cancel))) => {
                let Some(info) = cancel_goal_info(&cancel) else {
                    log::warn!("navigate_to_pose: cancel request dropped: unreadable");
                    continue;
                };
                let response = nav.cancel(&info, bridge);
                if let Err(e) = server.send_cancel_response(req, response) {
                    log::error!("navigate_to_pose: cancel response not sent: {e:?}");
                }
            }
            Ok(None) => break,
            Err(e) => log::warn!("navigate_to_pose: cancel request dropped: {e:?}"),
        }
    }
    for _ in 0..100 {
        match server.receive_result_request() {
            Ok(Some((req, r))) => nav.result_request(r.goal_id, req),
            Ok(None) => break,
            Err(e) => log::warn!("navigate_to_pose: result request dropped: {e:?}"),
        }
    }
    publish_action(server, nav);
}

/// The results due and the status array when it changed.
fn publish_action(server: &NavServer, nav: &mut Navigate<RmwRequestId>) {
    for r in nav.take_replies() {
        let response = GetResultResponse {
            status: r.status,
            result: r.result,
        };
        if let Err(e) = server.send_result(r.to, response) {
            log::error!("navigate_to_pose: result not sent: {e:?}");
        }
    }
    if let Some(status) = nav.take_status()
        && let Err(e) = server.send_goal_statuses(status)
    {
        log::error!("navigate_to_pose: status not published: {e:?}");
    }
    for (level, text) in nav.drain_log() {
        log::log!(level, "{text}");
    }
}

/// `/cmd_vel` as `Twist` or `TwistStamped` (`enable_stamped_cmd_vel`).
enum CmdVel {
    Plain(Publisher<Twist>),
    Stamped(Publisher<TwistStamped>, String),
}

impl CmdVel {
    fn publish(&self, twist: Twist, stamp: Time) {
        let result = match self {
            Self::Plain(p) => p.publish(twist).map_err(|e| format!("{e:?}")),
            Self::Stamped(p, frame) => p
                .publish(TwistStamped {
                    header: Header {
                        stamp,
                        frame_id: frame.clone(),
                    },
                    twist,
                })
                .map_err(|e| format!("{e:?}")),
        };
        if let Err(e) = result {
            log::error!("cmd_vel not published: {e}");
        }
    }
}

/// Takes every waiting message of `sub`, each handed to `f`; a message that does not
/// deserialise is dropped with a warning.
fn drain<M: serde::de::DeserializeOwned + 'static>(
    sub: &Subscription<M>,
    what: &str,
    mut f: impl FnMut(M),
) {
    loop {
        match sub.take() {
            Ok(Some((m, _))) => f(m),
            Ok(None) => return,
            Err(e) => log::warn!("{what}: message dropped: {e:?}"),
        }
    }
}

fn wall_time() -> Time {
    let t = SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .unwrap_or_default();
    Time::from_seconds(t.as_secs_f64())
}

#[allow(clippy::too_many_lines)]
fn run(params: Params, stop: &AtomicBool) -> Result<(), Fatal> {
    let context = participant()?;
    let mut node = context.new_node(
        NodeName::new("/", NODE_NAME)?,
        NodeOptions::new().enable_rosout(false),
    )?;
    let p = params.clone();
    let map = if p.map_topic.is_empty() {
        log::info!("map_topic is empty: navigating a disc around the robot from scans alone");
        None
    } else {
        // map_server's QoS: reliable, transient local, keep last 1.
        Some(subscribe::<OccupancyGrid>(
            &mut node,
            &p.map_topic,
            "nav_msgs",
            "OccupancyGrid",
            qos(true, true, 1),
        )?)
    };
    // Drivers publish scans best effort (SensorDataQoS); a reliable reader would not match.
    let scan = subscribe::<LaserScan>(
        &mut node,
        &p.scan_topic,
        "sensor_msgs",
        "LaserScan",
        qos(false, false, 5),
    )?;
    // Best effort matches both kinds of writer; only the latest odometry matters.
    let odom = subscribe::<Odometry>(
        &mut node,
        &p.odom_topic,
        "nav_msgs",
        "Odometry",
        qos(false, false, 10),
    )?;
    let goal = subscribe::<PoseStamped>(
        &mut node,
        &p.goal_topic,
        "geometry_msgs",
        "PoseStamped",
        qos(true, false, 1),
    )?;
    let tf = subscribe::<TFMessage>(
        &mut node,
        "tf",
        "tf2_msgs",
        "TFMessage",
        qos(true, false, 100),
    )?;
    let tf_static = subscribe::<TFMessage>(
        &mut node,
        "tf_static",
        "tf2_msgs",
        "TFMessage",
        qos(true, true, 100),
    )?;
    let clock = if p.use_sim_time {
        Some(subscribe::<Clock>(
            &mut node,
            "clock",
            "rosgraph_msgs",
            "Clock",
            qos(false, false, 1),
        )?)
    } else {
        None
    };
    let cmd = if p.enable_stamped_cmd_vel {
        CmdVel::Stamped(
            advertise(
                &mut node,
                &p.cmd_vel_topic,
                "geometry_msgs",
                "TwistStamped",
                qos(true, false, 1),
            )?,
            p.robot_base_frame.clone(),
        )
    } else {
        CmdVel::Plain(advertise(
            &mut node,
            &p.cmd_vel_topic,
            "geometry_msgs",
            "Twist",
            qos(true, false, 1),
        )?)
    };
    let status = advertise::<StringMsg>(
        &mut node,
        &p.status_topic,
        "std_msgs",
        "String",
        qos(true, true, 1),
    )?;
    // Latched, as RViz's marker displays take it (a volatile reader matches too).
    let obstacles = if p.obstacles_topic.is_empty() {
        None
    } else {
        Some(advertise::<MarkerArray>(
            &mut node,
            &p.obstacles_topic,
            "visualization_msgs",
            "MarkerArray",
            qos(true, true, 1),
        )?)
    };
    let server = if p.action_name.is_empty() {
        None
    } else {
        Some(action_server(&mut node, &p)?)
    };
    log::info!(
        "subscribed {} /{} /{} /{} /tf /tf_static; serving {}; publishing /{} ({}) every {:.0} ms and on each scan",
        map.as_ref()
            .map_or("(no map)".to_owned(), |_| format!("/{}", p.map_topic)),
        p.scan_topic,
        p.odom_topic,
        p.goal_topic,
        if p.action_name.is_empty() {
            "no action".to_owned()
        } else {
            format!(
                "/{} ({:?} service mapping)",
                p.action_name, p.service_mapping
            )
        },
        p.cmd_vel_topic,
        if p.enable_stamped_cmd_vel {
            "TwistStamped"
        } else {
            "Twist"
        },
        1e3 / p.controller_frequency
    );

    let mut bridge = Bridge::new(params);
    let mut nav: Navigate<RmwRequestId> = Navigate::new();
    let period = Duration::from_secs_f64(1.0 / p.controller_frequency);
    let mut next_tick = Instant::now();
    let mut sim_time: Option<Time> = None;
    let mut last_status = String::new();
    // Scan taken → command published, s.
    let mut latencies: Vec<f64> = Vec::new();
    while !stop.load(Ordering::SeqCst) {
        let now = Instant::now();
        if let Some(c) = &clock {
            drain(c, "clock", |m: Clock| sim_time = Some(m.clock));
        }
        drain(&tf_static, "tf_static", |m| bridge.on_tf(&m, now, true));
        drain(&tf, "tf", |m| bridge.on_tf(&m, now, false));
        if let Some(map) = &map {
            drain(map, "map", |m| bridge.on_map(&m));
        }
        drain(&odom, "odom", |m| bridge.on_odom(&m, now));
        drain(&goal, "goal", |m| nav.goal_topic(&m, &mut bridge, now));
        if let Some(server) = &server {
            serve(server, &mut nav, &mut bridge, now);
        }
        // Only the newest scan is used; older ones waiting are superseded.
        let mut newest = None;
        drain(&scan, "scan", |m| newest = Some(m));
        let scanned = newest.is_some();
        if let Some(m) = newest {
            bridge.on_scan(&m, now);
        }
        if scanned || now >= next_tick {
            let step = bridge.step(now);
            let stamp = if p.use_sim_time {
                sim_time.unwrap_or_default()
            } else {
                wall_time()
            };
            cmd.publish(step.twist, stamp);
            if let Some((id, feedback)) = nav.after_step(&step, &mut bridge, now, stamp)
                && let Some(server) = &server
                && let Err(e) = server.send_feedback(id, feedback)
            {
                log::warn!("navigate_to_pose: feedback not published: {e:?}");
            }
            if let Some(server) = &server {
                publish_action(server, &mut nav);
            }
            if scanned {
                latencies.push(now.elapsed().as_secs_f64());
            }
            next_tick = now + period;
            let text = match (&step.stop, step.mode) {
                (Some(s), _) => format!("stopped: {s}"),
                (None, Some(m)) => format!("moving: {m}"),
                (None, None) => "moving".to_owned(),
            };
            if text != last_status {
                if let Err(e) = status.publish(StringMsg { data: text.clone() }) {
                    log::warn!("status not published: {e:?}");
                }
                last_status = text;
            }
            // After the command, off the scan → cmd_vel path.
            if let Some(o) = &obstacles
                && let Some(m) = bridge.obstacle_markers(stamp)
                && let Err(e) = o.publish(m)
            {
                log::warn!("obstacle markers not published: {e:?}");
            }
        }
        for (level, text) in bridge.drain_log() {
            log::log!(level, "{text}");
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    // Shutdown: a zero command, twice (a reliable writer retransmits; the repeat covers a
    // reader that drops the first), and time for it to leave before the participant goes.
    log::warn!("stop: shutting down (signal); publishing a zero command");
    let stamp = if p.use_sim_time {
        sim_time.unwrap_or_default()
    } else {
        wall_time()
    };
    for _ in 0..2 {
        cmd.publish(Twist::default(), stamp);
        std::thread::sleep(Duration::from_millis(50));
    }
    let _ = status.publish(StringMsg {
        data: "stopped: shutting down".into(),
    });
    nav.shutdown();
    if let Some(server) = &server {
        publish_action(server, &mut nav);
    }
    std::thread::sleep(Duration::from_millis(100));
    if !latencies.is_empty() {
        latencies.sort_by(f64::total_cmp);
        let q = |f: f64| {
            #[allow(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                clippy::cast_precision_loss
            )]
            let i = ((latencies.len() - 1) as f64 * f).round() as usize;
            latencies[i] * 1e3
        };
        log::info!(
            "scan taken → cmd_vel published: median {:.2} ms, 95 % {:.2} ms, max {:.2} ms over {} scans",
            q(0.5),
            q(0.95),
            q(1.0),
            latencies.len()
        );
    }
    // Entities before their node, the node before its context: RustDDS logs an error for
    // each reader or writer dropped after its participant's event loop has gone.
    drop((
        cmd, status, obstacles, scan, odom, goal, tf, tf_static, clock, map, server,
    ));
    drop(node);
    drop(context);
    Ok(())
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let read = |p: &str| std::fs::read_to_string(p).map_err(|e| e.to_string());
    let (cli, level) = match parse_args(&args, &read) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("harmonav-ros2: {e}\n{USAGE}");
            std::process::exit(2);
        }
    };
    let level = match level.as_deref().map(str::to_ascii_lowercase).as_deref() {
        None | Some("info") => log::LevelFilter::Info,
        Some("debug") => log::LevelFilter::Debug,
        Some("warn") => log::LevelFilter::Warn,
        Some("error" | "fatal") => log::LevelFilter::Error,
        Some(other) => {
            eprintln!(
                "harmonav-ros2: --log-level {other:?}: expected debug, info, warn, error or fatal"
            );
            std::process::exit(2);
        }
    };
    let logger = Logger {
        level,
        start: Instant::now(),
    };
    log::set_max_level(log::LevelFilter::Debug);
    let _ = log::set_boxed_logger(Box::new(logger));
    let params = match cli {
        Cli::Help => {
            println!("{USAGE}");
            return;
        }
        Cli::Run(p) => *p,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    if let Err(e) = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst)) {
        eprintln!("harmonav-ros2: no signal handler: {e}");
        std::process::exit(1);
    }
    if let Err(Fatal(text, code)) = run(params, &stop) {
        eprintln!("harmonav-ros2: {text}");
        std::process::exit(code);
    }
}
