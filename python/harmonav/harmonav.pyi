"""harmonav: provably correct robot navigation with the harmonic navigation functions of
Loizou & Rimon, ``Θ = σ∘φ_k∘Φ`` (eq. ``phiseq``), in Rust with NumPy arrays in and out."""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union, overload

from typing_extensions import TypedDict, Unpack

import numpy as np
import numpy.typing as npt

__version__: str

# Any array-like of real numbers (lists, tuples, int, unsigned or float arrays of any width),
# cast to float64: one point ``[x, y]``, or an (N, 2) array of points. Errors name the argument:
# ``TypeError`` for values that are not real numbers or the wrong number of dimensions,
# ``ValueError`` for the wrong length or a ragged list.
_Point = npt.ArrayLike
_Points = npt.ArrayLike

class Shape:
    """A star-shaped region ``{c + r·u : r ≤ R(θ)}``: an obstacle or a workspace boundary.

    Immutable. ``copy.copy``, ``copy.deepcopy`` and pickle rebuild it from the call that made it
    (``circle``, ``ellipse``, ``polygon``, ``star`` or ``tabulated``)."""

    @property
    def center(self) -> npt.NDArray[np.float64]:
        """The centre ``c`` about which the shape is star-shaped, (2,)."""
    def contains(self, point_xy: _Point) -> bool:
        """Whether the point lies in the closed region."""
    @overload
    def signed_distance(self, points_xy: Sequence[float]) -> float: ...
    @overload
    def signed_distance(self, points_xy: _Points) -> Union[float, npt.NDArray[np.float64]]:
        """Signed distance to the outline, negative inside: a float for one point, an (N,)
        array for an (N, 2) array-like (NaN for a non-finite row). ``MemoryError`` if the batch
        cannot be allocated."""
    def outline(self, n: int = 256) -> npt.NDArray[np.float64]:
        """``n`` points on the outline, evenly spaced in angle, (n, 2). ``n`` is at most 2**24
        (16 777 216); above that, or when the array cannot be allocated, ``MemoryError``."""
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...
    def __copy__(self) -> Shape: ...
    def __deepcopy__(self, memo: Any) -> Shape: ...

def circle(center: _Point, radius: float) -> Shape:
    """A disc: ``R(θ) = r``."""

def ellipse(center: _Point, semi_axes: _Point, angle_deg: float = 0.0) -> Shape:
    """An ellipse: ``R(ψ) = ab/√(b² cos²ψ + a² sin²ψ)``, ``ψ = θ − angle``."""

def polygon(vertices: _Points, corner_radius: float) -> Shape:
    """A polygon (an (N, 2) array-like, N ≥ 3), star-shaped about its vertex centroid, with
    corners rounded to ``corner_radius``."""

def star(center: _Point, radius: float, harmonics: Sequence[Sequence[float]]) -> Shape:
    """A Fourier star ``R(θ) = r0 + Σ (a_n cos nθ + b_n sin nθ)``, harmonics ``(n, a_n, b_n)``.
    Each order ``n`` is a whole number from 1 to 1000 (the cap of scenario files); a larger one
    raises ``ValueError`` naming ``harmonics[i]``."""

def tabulated(center: _Point, radii: Sequence[float]) -> Shape:
    """A tabulated star: radii ``R_i`` (at least 8, finite, positive) at ``θ_i = 2πi/G`` about
    ``center``, monotone cubic cells in between; the form of a perceived radial hull."""

class Field:
    """``Θ(x) = σ(φ_k(Φ(x)))`` with every obstacle known.

    ``k`` is ``"auto"`` (``k = max(6(M + 1), 2·layer_ratio)``) or ``"paper"`` (``k = M + 1``); ``margin`` grows the
    obstacles and shrinks the boundary.

    Immutable: ``copy`` and ``deepcopy`` return the same object; pickle rebuilds it from the
    constructor's arguments (or, for ``Scenario.field()``, from the pickled scenario).
    """

    def __init__(
        self,
        boundary: Shape,
        obstacles: Sequence[Shape],
        goal: _Point,
        k: str = "auto",
        margin: float = 0.0,
    ) -> None: ...
    @property
    def k(self) -> float:
        """``k`` of ``φ_k``."""
    def eval(
        self, points_xy: _Points
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """``(theta (N,), grad (N, 2))`` at the rows of an (N, 2) array-like; NaN rows outside
        the free space or for non-finite input (``free`` is the mask). ``MemoryError`` if the
        copy of the points or the results cannot be allocated."""
    def free(self, points_xy: _Points) -> npt.NDArray[np.bool_]:
        """Whether each row lies in the free space, (N,). ``MemoryError`` as ``eval``."""
    def census(self) -> List[Dict[str, Any]]:
        """The critical points of ``Θ`` (theorem ``isNF``): dicts with ``x``, ``kind`` and
        ``eigenvalues``."""
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...
    def __copy__(self) -> Field: ...
    def __deepcopy__(self, memo: Any) -> Field: ...

class Navigator:
    """The navigator of a robot that does not know its map, over a star world
    (``Navigator(boundary, goal, …)``) or a floor plan (``FloorNavigator``, its subclass: the
    same options and methods).

    ``law="kinematic"``: ``u = −s(x)∇Θ/|∇Θ|``, the flow lines of eq. ``kinctrl``; under
    ``speed="auto"`` (the default) ``s = min(v_max, √(2a|x − x_d|))``: full speed until a braking
    distance, then a constant deceleration and a linear core (35 µm at the default ``v_max``):
    within any tolerance of the goal in finite time, and the hold never steps past it; under
    ``speed="paper"`` ``s = K√(2Θ)``, ``K = gain``. ``v_max`` (m/s, default ``K√2``) caps both.
    ``law="dynamic"``: ``f = −μ_p∇Ψ − λẋ`` (eq. ``dynctrllocal``) for a robot of mass ``mass``,
    whose speed stays below ``√(2μ/m)``; ``μ_p`` is ``mu`` but under the default
    ``damping="governed"``, where it is ``4·mu·max(1, ρ/5 m)`` (``ρ`` the boundary's largest
    radius) with a governor that keeps the speed below ``0.9·√(2μ/m)``.

    ``control_period`` is how long the loop holds each command; under ``hold="auto"`` every
    command is safe to hold for it (``hold="paper"``: the continuous law sampled as is).

    Fed by ``observe_scan``, the perception remembers the free space of its last
    ``free_memory`` scans (default 16; a static world), and with ``fit_range`` (m, default
    ``None``) fits a segment only once a hit is that near:
    ``max(radius + margin, range_min) + range_noise + 3·v_max·T_scan`` is recommended (§12.16;
    ``v_max`` the dynamic law's ``√(2μ/m)``, which brakes within each scan event's own room,
    §12.18). Under the dynamic law with ``damping="paper"`` it cuts the sector of ``d_min`` to
    ``fit_range − max_obstacle_depth`` (``max_obstacle_depth + 0.5`` is recommended there,
    docs/maths.md §12.11).

    Invalid parameters raise ``ValueError`` naming them (the ranges of scenario files), and so
    do parameters whose derived quantities (``d_min``, the speed bound, ``λ_c``) are not finite;
    a keyword that is not an option raises ``TypeError`` naming it. Both worlds check their
    options in one place.
    ``copy.copy``, ``copy.deepcopy`` and pickle give an independent navigator with the same
    known obstacles and state (the speed at the latest discovery, the last position, the
    movers and the deadlock rule's memory among them): it commands exactly as the original.
    Pickle stores the calls that made the state and that memory (``("mover-memory", …)``), not
    every command the mover filter changed: its size does not grow with a wait among movers.

    ``base="diff"`` (issue 53) makes it a differential-drive robot's navigator, commanded by
    ``command_pose(position, yaw)`` → ``(v, omega)`` with ``0 ≤ v ≤ v_max`` and
    ``|omega| ≤ omega_max`` (both required; ``v_max`` is still the kinematic law's top speed);
    ``base="holonomic"`` (the default) is ``command``'s robot. Kinematic law only. An unknown base,
    or a bound that is missing, not finite or not positive, is a ``ValueError`` naming it.
    ``a_max`` (m/s²) and ``alpha_max`` (rad/s²), both or neither, add acceleration limits:
    consecutive commands differ by at most ``a_max·h`` and ``alpha_max·h`` (the base starts at
    rest), and every command leaves the base room to brake (docs/unicycle.md §10).

    ``set_movers([...])`` (issue 54) gives it the movers of this period (``Mover``); every
    command is then filtered against where they can reach within the period: ``mode`` is
    ``"yielding"`` when the filter changed it, ``"overwhelmed"`` (and ``certified`` False) when
    no command could be certified against them.

    ``force_bound`` (N, the dynamic law only) bounds every force, ``|f| ≤ F``, and certifies a
    command only if the robot can still brake to rest at ``F/m`` inside the known free space
    and out of every mover's reach (docs/movers.md §2): ``mode`` is ``"bounded"`` when the
    bound changed the command, ``"braking"`` (and ``certified`` False) when even the full
    brake's way to rest is not certified. Not finite, not positive, or with the kinematic law:
    a ``ValueError`` naming it.

    ``comfort`` (m, default 0) is a distance the command keeps beyond the margin from every
    non-cooperative mover where it can (docs/movers.md §7, "Comfort"): it turns the nominal
    command only, and the mover filter still certifies every command. Negative or not finite:
    a ``ValueError`` naming it.

    Threads: calls on one navigator are serialised by a lock inside it; a call made while
    another thread's call runs (``observe_scan`` releases the GIL) waits for it instead of
    failing.
    """

    def __init__(
        self,
        boundary: Shape,
        goal: _Point,
        law: str = "kinematic",
        gain: float = 1.0,
        mass: float = 1.0,
        mu: float = 10.0,
        sensor: Tuple[float, float] = (1.0, 60.0),
        radius: float = 0.0,
        margin: float = 0.0,
        k: str = "auto",
        damping: str = "governed",
        rho_min: float = 0.05,
        control_period: Optional[float] = None,
        hold: str = "auto",
        speed: str = "auto",
        v_max: Optional[float] = None,
        range_noise: float = 0.02,
        max_obstacle_depth: float = 1.0,
        growth_threshold: float = 0.02,
        fit_range: Optional[float] = None,
        free_memory: int = 16,
        base: str = "holonomic",
        omega_max: Optional[float] = None,
        a_max: Optional[float] = None,
        alpha_max: Optional[float] = None,
        force_bound: Optional[float] = None,
        comfort: float = 0.0,
    ) -> None: ...
    def observe_scan(
        self,
        position: _Point,
        heading: float,
        ranges: Any,
        angle_min: float,
        angle_increment: float,
        range_max: float,
        range_min: float = 0.0,
    ) -> ScanUpdate:
        """Observes one range scan (``sensor_msgs/LaserScan`` fields) taken at ``position`` with
        ``heading`` (rad); ``ranges`` is a 1-D array-like of real numbers (booleans and complex
        numbers raise ``TypeError``, as for points). Hits explained by known shapes are dropped, the rest fitted to
        conservative stars that grow known obstacles or are added (docs/maths.md §12.6), under
        the priors ``range_noise``, ``max_obstacle_depth``, ``growth_threshold`` and ``rho_min``.
        ``ValueError`` (and nothing changed) for an invalid scan or pose, or a shape that would
        contain the robot or the goal, cross the boundary or overlap another ("the world as
        perceived is not a star world")."""
    @property
    def perceived(self) -> List[Tuple[int, Shape]]:
        """The perceived shapes (not grown) as ``(index among the obstacles, star)`` pairs."""
    @property
    def obstacles(self) -> List[Shape]:
        """Every known obstacle (not grown), in the navigator's order: the shapes given to
        ``add_obstacle`` and the perceived ones."""
    def add_obstacle(self, shape: Shape) -> int:
        """Adds a newly sensed obstacle; returns its index. ``ValueError`` leaves the navigator unchanged."""
    def command(self, x: _Point, v: Optional[_Point] = None) -> npt.NDArray[np.float64]:
        """The command to hold for ``control_period`` (a velocity or a force), (2,), always
        finite and, under ``hold="auto"``, safe to hold (``mode`` says how it was formed):
        ``ValueError`` (and nothing changed) where the robot's disc overlaps a known obstacle,
        for non-finite input, or for a command that would not be finite."""
    def command_pose(self, position: _Point, yaw: float) -> Tuple[float, float]:
        """``(v, omega)`` to hold for ``control_period`` at the pose ``(position, yaw)`` of a
        differential-drive robot (``base="diff"``): aligned descent, its arc over the period
        certified free of the known obstacles; ``0 ≤ v ≤ v_max``, ``|omega| ≤ omega_max``.
        ``ValueError`` (and nothing changed) on a holonomic navigator (naming ``base``), for a
        non-finite pose, and where ``command`` would raise. With movers set, the direction is
        the filtered one but the arc is not certified against the movers."""
    def set_goal_heading(self, yaw: Optional[float]) -> None:
        """Sets the goal yaw (rad, map frame) a differential-drive robot finishes at, or clears
        it (``None``, the default: ``command_pose`` as without one, bit for bit). Once the
        position is within 1 cm of the goal (``set_goal_tolerance``), ``command_pose`` turns in place: ``v = 0``,
        ``omega = clamp(k·wrap(yaw − θ), ±omega_max)`` (``k = min(10, 1/control_period)``;
        within the acceleration limits, if any), ``steer == "to-goal-heading"``, until the
        heading is within 1e-3 rad of it, then ``(0, 0)`` with ``steer == "arrived"``. Turning in
        place is safe for a disc robot with its axle at its centre (docs/unicycle.md section
        3.5). A non-finite yaw raises ``ValueError`` naming ``goal_yaw`` and changes nothing.
        Kept by pickle and copy."""
    @property
    def goal_heading(self) -> Optional[float]:
        """The goal yaw of ``set_goal_heading``, rad; ``None`` without one."""
    def set_goal_tolerance(
        self, xy: Optional[float] = None, yaw: Optional[float] = None, stateful: Optional[bool] = None
    ) -> None:
        """Where a goal with a yaw (``set_goal_heading``) has arrived: the turn in place begins
        within ``xy`` m of the goal and ends within ``yaw`` rad of the goal yaw (Nav2's
        ``xy_goal_tolerance`` and ``yaw_goal_tolerance``; defaults 0.01 m and 1e-3 rad; a bound
        not given keeps its value). ``stateful`` (Nav2's, default True): once a pose within
        ``xy`` has been commanded the radius latches (``goal_latched``): the robot only brakes
        (under acceleration limits) and turns in place, wherever it rolls, never driving back;
        False decides afresh at each command. A different tolerance releases the latch.
        Turning in place is safe anywhere, so no tolerance weakens a certificate. A bound that
        is not finite and positive raises ``ValueError`` naming ``xy_goal_tolerance`` or
        ``yaw_goal_tolerance`` and changes nothing. Kept by pickle and copy (the latch too)."""
    @property
    def goal_tolerance(self) -> Tuple[float, float]:
        """``(xy, yaw)`` of ``set_goal_tolerance``: m and rad."""
    @property
    def goal_stateful(self) -> bool:
        """Whether the goal's radius latches (``set_goal_tolerance(stateful=…)``)."""
    @property
    def goal_latched(self) -> bool:
        """Whether the goal's radius is latched: a pose within ``xy`` has been commanded since
        the goal yaw or the tolerance last changed."""
    def set_movers(self, movers: Sequence[Union[Mover, Dict[str, Any]]]) -> None:
        """Replaces the movers (``Mover``s, or dicts with its argument names as keys); ``[]``
        clears them. All or nothing: an invalid mover is a ``ValueError`` naming
        ``movers[i].field``. A command where the robot's disc overlaps a mover's as reported
        raises ``ValueError``."""
    @property
    def movers(self) -> List[Mover]:
        """The movers of the last ``set_movers``."""
    @property
    def certified(self) -> bool:
        """False only when the last command could not be certified against a mover
        (``mode == "overwhelmed"``)."""
    @property
    def steer(self) -> Optional[str]:
        """How the last ``command_pose`` formed ``(v, omega)``: ``"ahead"``, ``"shortened"``,
        ``"turning"``, ``"stopped"``, (with acceleration limits) ``"braking"``, or (with a goal
        yaw, ``set_goal_heading``) ``"to-goal-heading"`` and ``"arrived"``; ``None`` before it
        and after a ``command``."""
    @property
    def base(self) -> str:
        """``"holonomic"`` or ``"diff"``."""
    @property
    def omega_max(self) -> Optional[float]:
        """A differential-drive base's top turn rate, rad/s; ``None`` for a holonomic one."""
    @property
    def accel(self) -> Optional[Tuple[float, float]]:
        """A differential-drive base's acceleration limits ``(a_max, alpha_max)``; ``None``
        without them."""
    @property
    def force_bound(self) -> Optional[float]:
        """The dynamic law's force bound, N (``force_bound=``); ``None`` without one."""
    @property
    def comfort(self) -> float:
        """The comfort distance from non-cooperative movers, m (``comfort=``); 0 for none."""
    @property
    def mode(self) -> str:
        """How the last command was formed: ``"law"``, ``"capped"``, ``"recovering"``,
        ``"from-rest"`` (where the kinematic law's held step had come to rest away from the goal,
        at a saddle of Θ or in a narrow valley: the steepest certified descent of 16 directions),
        ``"escaping"`` (floor plans), ``"halted"`` (the last ``observe_scan`` was refused: zero
        velocity, or the force that stops the robot within the period, until a scan is
        accepted), ``"yielding"`` (the mover filter changed it, certified) or ``"overwhelmed"``
        (no command keeps out of every mover's reach: the least violation, not certified)."""
    @property
    def control_period(self) -> float:
        """The control period in force, s (default 0.01 kinematic, 0.001 dynamic)."""
    def clearance(self, x: _Point) -> float:
        """The certified distance from ``x`` to the nearest known grown obstacle or the shrunk
        boundary (on a floor plan: the boundary layer), m."""
    def theta(self, x: _Point) -> float:
        """``Θ(x)`` over the known obstacles (finite, or ``ValueError``)."""
    @property
    def k(self) -> float: ...
    @property
    def obstacle_count(self) -> int: ...
    @property
    def goal(self) -> npt.NDArray[np.float64]: ...
    @property
    def speed_bound(self) -> Optional[float]:
        """``√(2μ/m)`` for the dynamic law, ``None`` for the kinematic one."""
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...], List[Tuple[Any, ...]]]: ...
    def __setstate__(self, state: List[Tuple[Any, ...]]) -> None:
        """Rebuilds the navigator (a floor plan's on its map, not solved again) and replays
        ``state`` (``("add", shape)``, ``("command", x, v)``, ``("pose", x, yaw)``,
        ``("movers", [Mover, …])``, ``("scan", …)`` entries);
        ``ValueError``/``TypeError``, and nothing changed, if it does not replay."""
    def __copy__(self) -> Navigator: ...
    def __deepcopy__(self, memo: Any) -> Navigator: ...

class Mover:
    """A moving disc as perception reports it (issue 54): ``centre`` (m), the body's ``radius``
    (m), ``speed_bound`` (m/s), the report's ``error`` bound (m) and ``kind``:
    ``"noncooperative"`` (a person, a robot of another stack) or ``"reciprocal"`` (another
    harmonav robot taking ``1 − share`` of the avoidance; its ``error`` is allowed, the row is
    robust to it, docs/movers.md eq. robust). Immutable and picklable; a bad field is a
    ``ValueError`` naming it."""

    def __init__(
        self,
        centre: _Point,
        radius: float,
        speed_bound: float,
        error: float = 0.0,
        kind: str = "noncooperative",
        share: float = 0.5,
        velocity: Optional[_Point] = None,
    ) -> None: ...
    @property
    def centre(self) -> npt.NDArray[np.float64]: ...
    @property
    def velocity(self) -> Optional[npt.NDArray[np.float64]]:
        """The tracked velocity (m/s), if given: never used by the certificate; KeepRight's
        anticipation reads it."""
        ...
    @property
    def radius(self) -> float: ...
    @property
    def speed_bound(self) -> float: ...
    @property
    def error(self) -> float: ...
    @property
    def kind(self) -> str: ...
    @property
    def share(self) -> float: ...
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...

class MoverFilter:
    """The standalone certified mover filter: certifies any planner's velocity against movers
    for a disc robot of ``radius`` and ``margin`` (m), at most ``v_max`` fast (m/s), holding
    each velocity for ``control_period`` (s). ``ValueError`` names a bad argument."""

    def __init__(self, radius: float, margin: float, v_max: float, control_period: float) -> None: ...
    def filter(
        self,
        x: _Point,
        nominal: _Point,
        movers: Sequence[Union[Mover, Dict[str, Any]]],
        clearance: float = ...,
    ) -> Tuple[npt.NDArray[np.float64], str]:
        """``(velocity, mode)``: ``nominal`` clipped to ``|u| ≤ min(v_max, clearance/(2h))``
        (``"capped"`` if it was, else ``"law"``) when it keeps out of every mover's reach over
        the period; else the closest certified velocity (``"yielding"``); else the least
        violation, not certified (``"overwhelmed"``). ``clearance`` (default ∞) is the caller's
        certified distance to the static world grown by ``radius + margin``."""
    @property
    def radius(self) -> float: ...
    @property
    def margin(self) -> float: ...
    @property
    def v_max(self) -> float: ...
    @property
    def control_period(self) -> float: ...
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...

class ScanUpdate:
    """What one ``Navigator.observe_scan`` did (indices among the navigator's obstacles)."""

    @property
    def added(self) -> List[int]: ...
    @property
    def grown(self) -> List[int]: ...
    @property
    def absorbed(self) -> List[int]:
        """Obstacles merged into a grown one and removed (indices before the scan)."""
    @property
    def hits(self) -> int: ...
    @property
    def explained(self) -> int: ...
    @property
    def unfitted(self) -> int: ...
    @property
    def event_clearance(self) -> Optional[float]:
        """At an event, the distance from the robot to the changed grown shapes, m."""
    @property
    def changed(self) -> bool: ...

class RunResult:
    """The result of ``Scenario.run``."""

    summary: Dict[str, Any]
    t: npt.NDArray[np.float64]
    x: npt.NDArray[np.float64]
    v: npt.NDArray[np.float64]
    theta: npt.NDArray[np.float64]
    discoveries: List[Dict[str, Any]]

class Scenario:
    """A scenario file, validated as ``harmonav check`` does.

    Immutable: ``copy`` and ``deepcopy`` return the same object. Pickle stores the path and the
    text read from it; unpickling validates that text again (the file is not read again)."""

    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> Scenario:
        """Reads the file without the GIL. Raises ``ValueError`` naming the file, field and
        line of the first problem."""
    @property
    def name(self) -> str: ...
    @property
    def path(self) -> str: ...
    def field(self) -> Field:
        """``Θ`` with every obstacle known, grown by the robot's radius and margin (what
        ``harmonav eval`` evaluates)."""
    def shortest_path(self) -> Tuple[float, npt.NDArray[np.float64]]:
        """``(length, waypoints (K, 2))`` of the shortest collision-free path around the grown
        shapes (independent of ``Θ``)."""
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...
    def __copy__(self) -> Scenario: ...
    def __deepcopy__(self, memo: Any) -> Scenario: ...
    def run(
        self,
        model: Optional[str] = None,
        physics: str = "builtin",
        out: Optional[Union[str, PathLike[str]]] = None,
        *,
        controller: Optional[str] = None,
    ) -> RunResult:
        """Runs the scenario without the GIL, with ``model`` (``"kinematic"`` or ``"dynamic"``;
        None: the file's; ``controller`` is its deprecated old name). ``out``, a folder, receives summary.json,
        run.mcap and the figures as one set (a kinematic run removes a stale speed.svg and
        energy.svg there). ``out`` is checked before the run: an empty path, a path below a
        file, a dangling or looping link, an unwritable folder, a path too long or a folder
        named like an output raise ``ValueError`` and nothing runs. A failure to write after
        the run raises ``OSError`` whose ``result`` is the ``RunResult`` (and ``summary`` its
        summary); the previous outputs stay whole. Ctrl-C stops the run
        (``KeyboardInterrupt``) and leaves nothing of an unfinished ``out`` set."""

class FloorRunResult:
    """The result of ``FloorPlan.run``: ``summary`` (the dict of its summary.json) and ``x``,
    the kept positions (N, 2) from the start to the end."""

    summary: Dict[str, Any]
    x: npt.NDArray[np.float64]

class FloorPlan:
    """A floor-plan file (``[floor_plan]``: a polygon with holes, or a ROS map), its harmonic
    map solved on load (docs/maths.md §13).

    Immutable: ``copy`` and ``deepcopy`` return the same object. It does not pickle
    (``TypeError``): its map is solved from files another process may not have or may have
    changed; pass the path and call ``FloorPlan.load(path)`` there."""

    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> FloorPlan:
        """Reads the file and solves its map without the GIL. Raises ``ValueError`` naming the
        file, the field and the problem."""
    @property
    def name(self) -> str: ...
    @property
    def path(self) -> str: ...
    @property
    def starts(self) -> npt.NDArray[np.float64]:
        """``robot.start``, then the file's seeded ``[starts]``: (N, 2)."""
    @property
    def elements(self) -> int:
        """The boundary elements of the harmonic map."""
    @property
    def delta(self) -> float:
        """``δ``: the boundary layer's width outside the certified region, m."""
    def certify_level(self) -> Dict[str, Any]:
        """``c_δ`` certified over the walls (docs/maths.md §13.5), without the GIL: ``c_delta``
        (a lower bound of ``Θ`` on the edge of the certified region), ``c_delta_sampled``,
        ``phi_certified`` and ``phi_sampled`` (the same in ``phi_k``), ``evaluations``,
        ``unresolved``, ``c_slide`` and ``phi_slide`` (``c_s``, below which the slide along
        that edge cannot rest, §13.9: 1 and ``inf`` when it rests nowhere) and
        ``starts_certified`` (one bool per row of ``starts``: ``Θ(x₀) < c_δ`` or ``< c_s``:
        convergence from it is certified)."""
    def run(
        self,
        model: Optional[str] = None,
        start: Optional[_Point] = None,
        out: Optional[Union[str, PathLike[str]]] = None,
        physics: str = "builtin",
        heading: Optional[str] = None,
    ) -> FloorRunResult:
        """Runs the loop from ``start`` (default ``robot.start``) under ``model`` without the
        GIL and judges every guarantee (as ``harmonav run`` on the file). ``physics`` is
        ``"builtin"`` or ``"rapier"`` (the walls as colliders, cross-checked against a built-in
        run; ``harmonav run --physics rapier``). ``heading`` (``"auto"`` or ``"paper"``; None:
        the file's ``[robot] heading``) is the heading policy of either law (docs/maths.md
        §13.3–13.4). ``out``, a folder,
        receives run.mcap, trajectory.svg and summary.json as one set; it is checked before the run
        (``ValueError``), and a failure to write after it raises ``OSError`` whose ``result``
        is the ``FloorRunResult``. Ctrl-C stops the run (``KeyboardInterrupt``) and leaves
        nothing of an unfinished ``out`` set."""
    def __copy__(self) -> FloorPlan: ...
    def __deepcopy__(self, memo: Any) -> FloorPlan: ...

class _Options(TypedDict, total=False):
    """``Navigator``'s options after ``goal``, as keyword arguments (its defaults)."""

    law: str
    gain: float
    mass: float
    mu: float
    sensor: Tuple[float, float]
    radius: float
    margin: float
    k: str
    damping: str
    rho_min: float
    control_period: Optional[float]
    hold: str
    speed: str
    v_max: Optional[float]
    range_noise: float
    max_obstacle_depth: float
    growth_threshold: float
    fit_range: Optional[float]
    free_memory: int
    base: str
    omega_max: Optional[float]
    a_max: Optional[float]
    alpha_max: Optional[float]
    force_bound: Optional[float]
    comfort: float

class FloorNavigator(Navigator):
    """The navigator of a robot on a floor plan, a ``Navigator``: the walls are known (rings of
    points, or a ROS map), their harmonic map solved once on construction (without the GIL);
    star obstacles are added as shapes or perceived from scans, each without a new solve. The
    robot stays in the certified region ``W_δ``, at least ``max(radius + margin, δ)`` from the
    walls (``δ = max_element``, docs/maths.md §13). ``centre`` and ``heading`` are the floor
    plan's own options; ``**options`` are ``Navigator``'s, with its defaults, checked as it
    checks them. ``ValueError`` names the field (a map's error the file); a call that raises
    leaves the navigator as it was. ``mode`` may also be ``"escaping"`` (along the shortest path
    from a rest point of the hold).

    ``funnels=True`` (the kinematic law only) builds a chain of certified funnels towards
    intermediate goals over the walls (docs/maths.md §13.10; seconds to a minute on a map of a
    thousand elements) and follows it: convergence to the goal is then certified from every
    point of their union, most of the reachable free area where the goal's own level certifies
    little (``funnels``, ``funnel_at``).

    ``copy`` and ``deepcopy`` give an independent navigator with the same walls (the solved map
    shared), obstacles and state. Pickle stores the true walls as rings, the goal, the keyword
    arguments and the calls that made the state; unpickling solves the map again and replays
    them: the obstacles, the last commanded state and the discovery speed survive, not the
    memory of the hold's escapes (rest time, an escape in progress, ``escapes``), so the copy
    commands as the original except where an escape is under way or due."""

    def __init__(
        self,
        outer: _Points,
        goal: _Point,
        holes: Optional[Sequence[_Points]] = None,
        *,
        max_element: float = 0.2,
        centre: str = "solve",
        heading: str = "auto",
        funnels: bool = False,
        **options: Unpack[_Options],
    ) -> None: ...
    @staticmethod
    def from_map(
        yaml: Union[str, PathLike[str]],
        start: _Point,
        goal: _Point,
        *,
        speck_pixels: int = 0,
        simplify: float = 0.5,
        max_element: float = 0.2,
        centre: str = "solve",
        heading: str = "auto",
        funnels: bool = False,
        **options: Unpack[_Options],
    ) -> FloorNavigator:
        """The navigator on a ROS map_server map (the free component holding the goal; start
        and goal in world coordinates). ``ValueError`` names the file and the problem."""
    def wall_distance(self, x: _Point) -> float:
        """The distance to the true walls (negative in a wall), m."""
    @property
    def delta(self) -> float:
        """``δ``, the width of the boundary layer, m."""
    @property
    def elements(self) -> int:
        """The number of boundary elements of the harmonic map."""
    @property
    def escapes(self) -> int:
        """Escapes begun from rest points of the hold's slide (docs/maths.md §13.7)."""
    @property
    def funnels(self) -> Optional[Dict[str, Any]]:
        """The chain followed (``funnels=True``), or ``None``: ``count``,
        ``certified_fraction`` (of the free area reachable from the goal), ``deepest``,
        ``goals`` (each ``((x, y), parent index or None)``) and ``current`` (the funnel the
        robot was last in, or ``None``)."""
    def funnel_at(self, x: _Point) -> Optional[int]:
        """The funnel the robot would follow from ``x`` (``None``: convergence from ``x`` is not
        certified by the chain, or there is no chain)."""
    def __copy__(self) -> FloorNavigator: ...
    def __deepcopy__(self, memo: Any) -> FloorNavigator: ...

class SweepResult:
    """The result of ``sweep``."""

    starts: npt.NDArray[np.float64]
    outcomes: npt.NDArray[np.str_]
    times: npt.NDArray[np.float64]
    reached: npt.NDArray[np.bool_]
    report: Dict[str, Any]

def sweep(
    scenario: Scenario,
    starts: Union[int, _Points],
    seed: int = 0,
    model: Optional[str] = None,
    *,
    controller: Optional[str] = None,
) -> SweepResult:
    """Many starts with every obstacle known, in parallel: a count of seeded random starts or an
    (N, 2) array, 1 to 1 000 000 of them (else ``ValueError``, as ``harmonav sweep``). A start
    outside the free space is the outcome ``"invalid-start"`` (its report failure names
    ``starts[i]``), not an error. Ctrl-C stops the sweep within a part of two starts per core
    (``KeyboardInterrupt``)."""

# A run configuration of ``run_batch``: ``generator="quality"`` with ``obstacles`` and ``seed``,
# or ``scenario`` (a path naming the file) with optional ``scenario_text``; the overrides
# ``model`` (the robot model, the spec's ``law``), ``k``, ``damping``, ``speed``, ``sensing``,
# ``margin``, ``max_time``, ``physics`` (None: the world's own); ``start`` ``[x, y]`` with
# ``start_index``. A record's ``effective`` is the configuration as run.
_RunConfig = Dict[str, Any]

def run_batch(
    runs: List[_RunConfig], threads: int = 1, shortest: bool = True
) -> List[Dict[str, Any]]:
    """Runs every configuration through ``harmonav run``'s library call on ``threads`` threads
    (0: every core) without the GIL: one record per run, in order. A run that cannot be made (a
    bad configuration, a world the scenario layer refuses, a run error, a panic) is a record with
    its ``error``; a start outside the free space has the outcome ``"invalid-start"``. The same
    configuration gives the same record, bit for bit (docs/experiments.md lists the keys)."""

def check_run_config(config: _RunConfig, prepare: bool = False) -> None:
    """Checks a run configuration as ``run_batch`` reads it (with ``prepare``, also its world
    with its overrides, through the scenario layer); raises ``ValueError`` naming the key."""

def random_start_points(config: _RunConfig, count: int, seed: int) -> List[List[float]]:
    """``count`` seeded free starts in the world of ``config``, as ``harmonav sweep --starts
    count --seed seed`` draws them."""

def study_table(rows: List[Dict[str, Any]]) -> str:
    """The Markdown table of an experiment's records (a list of row dicts with the report's
    columns; a missing column or ``None`` is a value the run does not have; the optional
    ``outcome`` and ``conservatism`` add the columns "not arrived" and "perceived/true area"),
    as ``cargo xtask quality`` prints it: ``harmonav_bench::table::table``, the one tabulation
    of the project."""

def study_cells(rows: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    """The cells of the records ``rows`` in the table's order: each a dict of the cell's
    ``world`` (None for generated worlds), ``obstacles``, ``law``, ``policy``, ``k``,
    ``sensing``, ``margin``, ``physics``, ``max_time``, its ``runs``, ``errors``, ``reached``,
    ``guarantees_held``, ``collisions``, ``ratio``, ``time``, ``steps`` (median, p90, max),
    ``min_clearance``, ``overshoot``, ``command_us`` (median, p90, max of the cost of one
    command, NaN where no run measured it), ``conservatism`` (median, p90, max of the perceived
    over the true obstacle area of lidar runs, NaN where none recorded it), ``not_arrived`` (a
    dict of outcome kind to the runs that did not arrive), and the ``ratios`` and
    ``arrived_times`` of the runs that arrived."""
