"""Type stubs of the native extension ``tailor._tailor`` (checked against the built module by
``tests/test_stub.py``)."""

from os import PathLike
from typing import Any, Literal, Sequence

import numpy as np
import numpy.typing as npt

__version__: str
DEFAULT_SEAM_STIFFNESS: float
DEFAULT_SEAM_BEND_STIFFNESS: float
DEFAULT_THICKNESS: float
DEFAULT_PIN_STIFFNESS: float
DEFAULT_FRICTION: tuple[float, float]
#: The garment setup's defaults (`Garment.setup`'s keys).
DEFAULT_SETUP: dict[str, Any]
#: The painted maps a garment's setup applies (`Garment.set_painted`).
PAINTED_MAPS: list[str]
MESHER_VERSION: int

ArrayLike = npt.ArrayLike
F32 = npt.NDArray[np.float32]

class TailorError(Exception):
    """Base class of every error Tailor raises."""

class InvalidMeshError(TailorError, ValueError): ...
class InvalidParameterError(TailorError, ValueError): ...
class SeamError(TailorError, ValueError): ...
class PatternError(TailorError, ValueError): ...
class TailorIOError(TailorError, OSError): ...
class SimulationError(TailorError, RuntimeError): ...
class CancelledError(TailorError): ...
class InternalError(TailorError, RuntimeError):
    """A bug in Tailor: a Rust panic caught at the boundary."""

class Fabric:
    """A piece's material. `u` is the pattern's x axis, `v` its y axis: `stretch` acts along u
    (and v unless `stretch_v`), `bend` on hinges whose edge runs along u (and every hinge unless
    `bend_bias`/`bend_v`, linear in the edge's angle between them)."""

    density: float
    stretch: float
    shear: float
    #: The quadratic hinge model's stiffness: a flexural rigidity of `HINGE_ENERGY_PER_RIGIDITY`
    #: x bend N·m.
    bend: float
    #: Stretch stiffness along v, N/m (None: `stretch`).
    stretch_v: float | None
    #: Bending of hinges on the bias, 45 degrees (None: the mean of u's and v's).
    bend_bias: float | None
    #: Bending of hinges along v (None: `bend`).
    bend_v: float | None
    def __init__(
        self,
        density: float | None = None,
        stretch: float | None = None,
        shear: float | None = None,
        bend: float | None = None,
        *,
        stretch_v: float | None = None,
        bend_bias: float | None = None,
        bend_v: float | None = None,
    ) -> None: ...
    def directions(self) -> dict[str, float]:
        """`stretch_u`, `stretch_v`, `bend_u`, `bend_bias`, `bend_v` as the solver takes them."""
    @staticmethod
    def named(name: str) -> Fabric:
        """The fabric library's fabric `name` as the solver's fabric."""

#: The hinge model's bending energy over the continuum energy of a rigidity equal to `bend` (3).
HINGE_ENERGY_PER_RIGIDITY: float

def fabric_library() -> list[dict[str, Any]]:
    """Every measured fabric, lightest first: `name`, `description`, `density`, `stretch_u`,
    `stretch_v`, `shear`, `rigidity_u`, `rigidity_bias`, `rigidity_v`, `rigidity`, `fabric`."""

class Settings:
    substeps: int
    iterations: int
    tolerance: float
    method: str
    gravity: tuple[float, float, float]
    air_damping: float
    ramp_enabled: bool
    ramp_closing_damping: float
    ramp_gap_threshold: float
    ramp_closed_fraction: float
    ramp_release_gap: float
    ramp_release_time: float
    ramp_closing_speed: float
    ramp_closing_gravity: float
    ramp_closing_hold: float
    ramp_closing_hold_distance: float
    chebyshev_rho: float | None
    colouring_seed: int
    # The two-level global step (coarse-grid correction; CPU only).
    two_level: bool
    def __init__(self, **kwargs: Any) -> None: ...
    @staticmethod
    def preset(name: str) -> Settings: ...
    @staticmethod
    def presets() -> list[str]: ...

class Simulation:
    num_particles: int
    num_triangles: int
    positions: F32
    velocities: F32
    masses: F32
    settings: Settings
    thickness: float
    triangles: npt.NDArray[np.uint32]
    rest: F32
    edges: npt.NDArray[np.uint32]
    def seam_pairs(self) -> list[dict[str, Any]]: ...
    def __init__(
        self,
        positions: ArrayLike,
        triangles_: ArrayLike,
        rest: ArrayLike,
        fabric: Fabric | None = None,
        settings: Settings | None = None,
        backend: str = "auto",
    ) -> None: ...
    # Backend: "auto" | "cpu" | "gpu"; `backend` is the one in use ("cpu" or "gpu").
    backend: str
    adapter: str | None
    # {"context_made": bool, "seconds": float} on the GPU (the shared context made or reused).
    gpu_setup: dict[str, Any] | None
    backend_warning: str | None
    def set_backend(self, backend: str) -> None: ...
    # CPU threads of this simulation's own (None: the process's pool, one per core).
    threads: int
    def set_threads(self, threads: int | None = None) -> None: ...
    def set_mass_scale(self, scale: ArrayLike) -> None: ...
    def set_triangle_stiffness(self, stretch: ArrayLike, shear: ArrayLike, stretch_v: ArrayLike | None = None) -> None:
        """Stretch (along u, and v unless `stretch_v`) and shear stiffness per triangle, N/m."""
    def set_triangle_bending(self, bend: ArrayLike) -> None: ...
    def set_triangle_grain(self, angle: ArrayLike) -> None:
        """The fabric's u axis per triangle, radians from the pattern's x axis (0: the pattern's axes)."""
    def set_bending_rest_pose(self, pose: ArrayLike | None = None) -> None: ...
    def add_seam(
        self, a: ArrayLike, b: ArrayLike, stiffness: float = 10000.0, bend_stiffness: float = 1e-5, name: str = "seam"
    ) -> int: ...
    def add_weighted_seam(
        self,
        a_vertices: ArrayLike,
        a_weights: ArrayLike,
        b_vertices: ArrayLike,
        b_weights: ArrayLike,
        stiffness: float = 10000.0,
        bend_stiffness: float = 1e-5,
        name: str = "seam",
    ) -> int: ...
    def pin(self, particles: ArrayLike, targets: ArrayLike | None = None) -> None: ...
    def unpin(self, particles: ArrayLike) -> None: ...
    def add_attachments(self, particles: ArrayLike, targets: ArrayLike, weight: float) -> None: ...
    def set_attachment_targets(self, targets: ArrayLike) -> None: ...
    def add_sphere_collider(
        self,
        center: Sequence[float],
        radius: float,
        static_friction: float = 0.5,
        kinetic_friction: float = 0.3,
    ) -> None: ...
    def add_plane_collider(
        self,
        point: Sequence[float],
        normal: Sequence[float],
        static_friction: float = 0.5,
        kinetic_friction: float = 0.3,
    ) -> None: ...
    def add_capsule_collider(
        self,
        a: Sequence[float],
        b: Sequence[float],
        radius: float,
        static_friction: float = 0.5,
        kinetic_friction: float = 0.3,
    ) -> None: ...
    def step(self, dt: float, frames: int = 1) -> dict[str, Any]: ...
    def step_async(
        self, dt: float, frames: int = 1, *, measure: bool = False, collider: int | None = None
    ) -> Pending:
        """`step` on a native thread (no Python runs there): returns at once; the simulation
        says busy until `Pending.finish`. With `measure` its statistics hold "metrics", the
        `metrics(collider)` of the state reached, computed on the same thread."""
    def metrics_async(self, collider: int | None = None) -> Pending:
        """`metrics` on a native thread, as `step_async`."""
    def seam_gaps(self) -> tuple[float, float]: ...
    def colour_count(self) -> int: ...
    def state_hash(self) -> int: ...
    def measure_step(
        self,
        dt: float,
        method: str = "chebyshev",
        iterations: int = 100,
        reference_iterations: int = 5000,
        reference_tolerance: float = 1e-7,
    ) -> dict[str, Any]: ...
    # Mesh colliders, collision levels, friction, self-collision, quality metrics.
    num_mesh_colliders: int
    particle_levels: npt.NDArray[np.int32]
    self_collision: dict[str, Any]
    def add_mesh_collider(
        self,
        vertices: ArrayLike,
        triangles_: ArrayLike,
        static_friction: float = 0.5,
        kinetic_friction: float = 0.3,
        cell_size: float | None = None,
        insertion: str = "paper_or_plane",
    ) -> int: ...
    def set_collider_positions(self, collider: int, positions: ArrayLike) -> None: ...
    def collider_positions(self, collider: int) -> F32: ...
    def set_collider_levels(self, collider: int, levels: ArrayLike) -> None: ...
    def set_collider_friction(self, collider: int, static_friction: float, kinetic_friction: float) -> None: ...
    def attach_to_collider(self, particles: ArrayLike, collider: int, stiffness: float) -> None:
        """Attach `particles` softly (`stiffness` N/m each) to mesh collider `collider`: each is
        bound where it is now to the nearest collider triangle and rides on it as the collider
        moves and deforms. Runs on the CPU (the GPU falls back with a warning)."""
    def detach_from_collider(self, particles: ArrayLike | None = None) -> None: ...
    # Particles attached to a mesh collider (uint32) and their current targets (k, 3).
    collider_attached: npt.NDArray[np.uint32]
    collider_attachment_targets: F32
    # Particles the body holds while the seams close (Settings.ramp_closing_hold; uint32).
    closing_holds: npt.NDArray[np.uint32]
    def set_particle_levels(self, levels: ArrayLike) -> None: ...
    def set_particle_friction(
        self, static_friction: ArrayLike | None = None, kinetic_friction: ArrayLike | None = None
    ) -> None: ...
    def set_self_collision(
        self,
        enabled: bool = True,
        radius: float | None = None,
        static_friction: float = 0.3,
        kinetic_friction: float = 0.2,
        contacts: Literal["spheres", "triangles"] = "spheres",
    ) -> None: ...
    def fit_maps_async(self, collider: int | None = None) -> Pending:
        """`fit_maps` on a native thread (as `step_async`); `finish()` returns its dict."""
        ...
    def fit_maps(self, collider: int | None = None) -> dict[str, F32 | None]:
        """Per-particle fit maps of the current state, as garment tools show to judge fit:
        ``strain`` (the largest stretch round each particle against its pattern, area-weighted
        over its triangles: 0.05 is 5 %), and with mesh collider ``collider`` ``distance``
        (signed distance to its surface, metres, positive outside) and ``pressure`` (the body's
        push on the cloth at rest, pascals: the cloth's stretch, shear and weight it balances,
        per particle area, where the particle is within the thickness + 2 mm of the surface;
        0 elsewhere). Without a collider both are None."""
        ...
    def metrics(self, collider: int | None = None) -> dict[str, Any]:
        """Quality of the current state: "penetration_count", "penetration_max_depth" (into
        mesh collider `collider`, 0 without one), "self_intersections", "seam_gap",
        "strain_max", "strain_mean", "kinetic_energy", "particles", "centroid" (the particles'
        mean, [x, y, z]), "top" (the mean of the highest twentieth against gravity: where the
        garment hangs from; the centroid without gravity), "on_body_fraction" (share of the particles within
        VERDICT_THRESHOLDS["on_body_distance_m"] (10 cm) of the collider's surface; None without
        one), "collider_centroid" (its surface's area-weighted centroid; None without one) and
        "seams_closing" (the garment is still being assembled). `judge` reads these."""

class Pending:
    """A step or a measurement on a native thread (`Simulation.step_async`, `metrics_async`)."""

    def done(self) -> bool: ...
    def wait(self, timeout: float | None = None) -> bool: ...
    def finish(self) -> dict[str, Any]:
        """What the synchronous call returns (a step's statistics with "wall_s"), waiting if
        needed; gives the solver back; raises the call's error. Once only."""

def sewn_tube(
    width: float = 0.5,
    height: float = 0.6,
    edge: float = 0.02,
    gap: float = 0.1,
    bottom: float = 0.0,
    seam_stiffness: float = 1000.0,
) -> dict[str, Any]: ...

def read_mesh(path: str | PathLike[str]) -> tuple[F32, npt.NDArray[np.uint32]]: ...

def write_obj(
    path: str | PathLike[str], positions: ArrayLike, triangles: ArrayLike, uv: ArrayLike | None = None
) -> None: ...

class Pc2Stream:
    """A PC2 cache written frame by frame into its own path, a valid cache after every frame
    (a crash or a kill keeps every frame finished; `resume` cuts off a frame cut short)."""

    num_samples: int
    timing: tuple[float, float]
    def __init__(
        self, path: str | PathLike[str], num_points: int, start_frame: float = 0.0, sample_rate: float = 1.0
    ) -> None: ...
    @staticmethod
    def resume(path: str | PathLike[str], num_points: int, keep: int | None = None) -> Pc2Stream: ...
    def push(self, points: ArrayLike) -> None: ...

class AnimatedMesh:
    num_vertices: int
    triangles: npt.NDArray[np.uint32]
    animations: list[tuple[str, float]]
    def __init__(self, path: str | PathLike[str]) -> None: ...
    def positions_at(self, time: float, animation: int | None = 0) -> F32: ...

def read_pc2(path: str | PathLike[str]) -> dict[str, Any]: ...
def check_outputs(
    inputs: Sequence[tuple[str, str | PathLike[str]]], outputs: Sequence[tuple[str, str | PathLike[str]]]
) -> None: ...
def sidecar_path(path: str | PathLike[str]) -> PathLike[str]: ...
def check_playback(fps: float, frames: int | None = None) -> None: ...
def write_pc2(
    path: str | PathLike[str], frames: ArrayLike, start_frame: float = 0.0, sample_rate: float = 1.0
) -> None: ...
def penetration(points: ArrayLike, vertices: ArrayLike, triangles_: ArrayLike) -> dict[str, Any]: ...
def count_self_intersections(vertices: ArrayLike, triangles_: ArrayLike) -> int: ...
def self_intersecting_pairs(
    vertices: ArrayLike, triangles_: ArrayLike, joined: ArrayLike | None = None
) -> npt.NDArray[np.uint32]:
    """The pairs `count_self_intersections` counts, (k, 2), `i < j`, sorted; vertices `joined`
    in pairs (k, 2) (sewn together) count as one."""
    ...
def edge_strain(positions: ArrayLike, edges: ArrayLike, rest_lengths: ArrayLike) -> dict[str, float]: ...
def kinetic_energy(velocities: ArrayLike, masses: ArrayLike) -> float: ...
def max_seam_gap(positions: ArrayLike, pairs_: ArrayLike) -> float: ...
def judge_unfinished(seams_closing: bool, seam_gap: float) -> dict[str, Any] | None:
    """The verdict on a run's last frame beyond `judge`'s: {"check": "open", "reason"} when its
    seams were still closing (the run ended before the garment was assembled, so `judge` judged
    none of its frames but on NaN), else None. `seam_gap` is that frame's widest gap, metres."""

def judge(metrics: dict[str, Any], start: dict[str, Any] | None = None, nan: bool = False) -> dict[str, Any]:
    """The checks a frame fails, given its `Simulation.metrics` (with a collider), those of the
    frame the run started from (`start`; the frame itself when None) and whether its solve
    diverged (`nan`). Returns {"centroid_shift_m": float, "top_shift_m": float, "failed":
    [{"check", "reason"}, ...]}, `failed` empty when the frame passes, else in this order:

    * "fell": assembled, the garment's centroid moved more than 20 cm from `start`'s and its top
      (the mean of its highest twentieth against gravity, `metrics["top"]`: where it hangs from)
      more than 10 cm, each relative to the collider's surface centroid (a walking body carries
      its garment), or under 25 % of its particles are within 10 cm of the collider's surface;
    * "open": assembled, a seam is open wider than 1 cm;
    * "inside": assembled, a particle is deeper than 1 cm inside the collider, or more than 1 % of
      the particles are inside it;
    * "nan": `nan` is true.

    "Assembled": no seam is still closing (`metrics["seams_closing"]` false); frames of the
    assembly are judged on "nan" only. The thresholds by name: `VERDICT_THRESHOLDS`. A missing
    or mistyped field is an InvalidParameterError."""

#: The verdict's thresholds (see `judge`): "on_body_distance_m" 0.10, "on_body_min" 0.25,
#: "fell_shift_m" 0.20, "fell_top_shift_m" 0.10, "open_gap_m" 0.01, "inside_depth_m" 0.01, "inside_share" 0.01, and
#: "checks", the check names in verdict order.
VERDICT_THRESHOLDS: dict[str, Any]
# Patterns, triangulation, seams and garments.

class Piece:
    name: str
    outline: npt.NDArray[np.float64]
    holes: list[npt.NDArray[np.float64]]
    internal_lines: list[npt.NDArray[np.float64]]
    notches: npt.NDArray[np.float64]
    fixed_vertices: list[int]
    #: The grain line's two ends, or None when the file has none.
    grain: tuple[tuple[float, float], tuple[float, float]] | None
    placement: dict[str, Any] | None
    edges: list[tuple[int, int]]
    def to_json(self) -> str: ...
    @staticmethod
    def from_json(text: str) -> Piece: ...

class Pattern:
    source: str
    pieces: list[Piece]
    stitches: list[tuple[tuple[int, int], tuple[int, int]]]
    sizes: list[str]
    size: str | None

class PieceMesh:
    name: str
    edge_length: float
    rest: F32
    triangles: npt.NDArray[np.uint32]
    contour: npt.NDArray[np.uint32]
    contour_param: npt.NDArray[np.float64]
    contour_length: float
    corners: list[int]
    span_map: list[tuple[int, int]]
    quality: dict[str, Any]
    def contour_point(self, i: int) -> tuple[float, float]: ...

class ContourPath:
    positions: list[int]
    direction: str
    def __init__(self, positions: Sequence[int], direction: str = "ccw") -> None: ...
    def vertices(self, mesh: PieceMesh) -> list[int]: ...
    def length(self, mesh: PieceMesh) -> float: ...

class Seam:
    name: str
    mode: str
    a: dict[str, Any]
    b: dict[str, Any]
    stiffness: float
    bend_stiffness: float
    def __init__(
        self,
        name: str,
        a: dict[str, Any],
        b: dict[str, Any],
        mode: str = "equal",
        stiffness: float = 1.0,
        bend_stiffness: float = 1.0,
    ) -> None: ...
    @staticmethod
    def from_paths(
        name: str,
        piece_a: int,
        mesh_a: PieceMesh,
        path_a: ContourPath,
        piece_b: int,
        mesh_b: PieceMesh,
        path_b: ContourPath,
        mode: str = "equal",
    ) -> Seam: ...
    def resolve(self, meshes: Sequence[PieceMesh]) -> dict[str, Any]: ...

class Garment:
    pieces: list[Piece]
    edge_lengths: list[float]
    #: Each piece's placement in effect (its own, else its pattern piece's), as `from_parts` takes it.
    placements: list[dict[str, Any] | None]
    #: Each piece's bend as `from_parts` and `set_bend` take it.
    bends: list[dict[str, Any] | None]
    meshers: list[int]
    seams: list[Seam]
    warnings: list[str]
    settings_json: str
    particle_params: list[tuple[str, int, npt.NDArray[Any]]]
    #: The typed setup (fabric per piece, thickness, friction, self-collision, pins, seam
    #: stiffness, collider levels); assign a dict to change it.
    setup: dict[str, Any]
    build_warnings: list[str]
    @staticmethod
    def from_pattern(
        path: str,
        edge: float = 0.01,
        size: str | None = None,
        units: str | None = None,
        tolerance: float = 0.0005,
        unfold: bool = True,
        quantities: bool = True,
    ) -> Garment: ...
    @staticmethod
    def from_parts(
        pieces: Sequence[Piece],
        edge_lengths: Sequence[float],
        seams: Sequence[Seam],
        placements: Sequence[dict[str, Any] | None] | None = None,
        bends: Sequence[dict[str, Any] | None] | None = None,
        meshers: Sequence[int] | None = None,
        positions: Sequence[ArrayLike | None] | None = None,
    ) -> Garment: ...
    @staticmethod
    def load(path: str) -> Garment: ...
    def set_painted(self, name: str, piece: int, values: ArrayLike, painted: ArrayLike | None = None) -> None: ...
    def clear_painted(self, name: str | None = None) -> None: ...
    def set_collider_levels(self, levels: ArrayLike | None = None) -> None: ...
    def collider_levels(self, num_vertices: int) -> tuple[npt.NDArray[np.int32] | None, list[str]]: ...
    def attach_groups(self) -> list[tuple[npt.NDArray[np.int64], float]]: ...
    def pin_weights(self) -> list[tuple[float, npt.NDArray[np.int64]]]: ...
    def apply_fabric(self, sim: Simulation) -> list[str]: ...
    def apply_friction(self, sim: Simulation) -> list[str]: ...
    def apply_collision(self, sim: Simulation) -> list[str]: ...
    def seam_pairs(self) -> list[dict[str, Any]]: ...
    def save(self, path: str) -> None: ...
    def meshes(self) -> list[PieceMesh]: ...
    def add_seam(self, seam: Seam) -> int: ...
    def set_resolution(self, piece: int, edge: float) -> PieceMesh: ...
    def set_bend(
        self,
        piece: int,
        axis_point: Sequence[float],
        axis_direction: Sequence[float],
        angle_deg: float,
        symmetry: tuple[Sequence[float], Sequence[float]] | None = None,
        threshold: float = 0.0,
        radius: float | None = None,
        mode: str = "roll",
        taper_deg: float = 0.0,
    ) -> None: ...
    def build_simulation(
        self,
        fabric: Fabric | None = None,
        settings: Settings | None = None,
        seam_stiffness: float | None = None,
        seam_bend_stiffness: float | None = None,
        gap: float = 0.05,
        backend: str = "auto",
        ride: bool = True,
    ) -> tuple[Simulation, list[int]]: ...
    def welded(self, positions: ArrayLike | None = None, gap: float = 0.05) -> WeldedMesh: ...

def read_pattern(
    path: str,
    size: str | None = None,
    units: str | None = None,
    tolerance: float = 0.0005,
    unfold: bool = True,
    quantities: bool = True,
) -> Pattern:
    """`unfold`: a DXF piece drawn as a half with a mirror line (cut on the fold) becomes the whole piece.
    `quantities`: a DXF piece is read as many times as its `Quantity:` says (a pair as the piece and its
    mirror image, named `R` and `L`; a piece cut 0 times left out)."""
def list_sizes(path: str) -> list[str]: ...
def triangulate(piece: Piece, edge: float = 0.01, mesher: int | None = None) -> PieceMesh: ...
def nearest_contour_position(mesh: PieceMesh, point: tuple[float, float]) -> int: ...
def shortest_path(mesh: PieceMesh, start: int, end: int) -> ContourPath: ...
def candidate_paths(mesh: PieceMesh, b1: int, n: int) -> tuple[ContourPath, ContourPath]: ...
def nearer_candidate(mesh: PieceMesh, b1: int, n: int, point: tuple[float, float]) -> ContourPath: ...
def find_corners(mesh: PieceMesh, max_angle_deg: float = 150.0) -> list[int]: ...
def nearest_corner_segment(mesh: PieceMesh, corners: Sequence[int], point: tuple[float, float]) -> ContourPath: ...
def bend(
    positions: ArrayLike,
    rest: ArrayLike,
    axis_point: Sequence[float],
    axis_direction: Sequence[float],
    angle_deg: float,
    symmetry: tuple[Sequence[float], Sequence[float]] | None = None,
    threshold: float = 0.0,
    radius: float | None = None,
    mode: str = "roll",
    taper_deg: float = 0.0,
) -> F32: ...

#: The places `body_places` finds, in its order.
PLACE_NAMES: list[str]

def body_places(
    vertices: ArrayLike,
    triangles_: ArrayLike,
    up: str | Sequence[float] | None = None,
    front: str | Sequence[float] | None = None,
) -> list[dict[str, Any]]:
    """The arrangement places on a humanoid body (issue 25), found from its shape: dicts
    {"name", "origin", "axis", "facing", "left", "up", "length", "radius", "reach"} in the order
    of `PLACE_NAMES`. `up` ("y" when None) and `front` (found from the feet when None): an axis
    name such as "-z" or a 3-vector. A body that is not a standing humanoid is an
    InvalidMeshError naming the part not found."""

def place_on_body(
    rest: ArrayLike,
    place: dict[str, Any],
    clearance: float = 0.03,
    side: str = "centre",
    around_deg: float = 0.0,
    along: str | None = None,
    offset: float = 0.0,
    min_radius: float = 0.0,
    grain: tuple[float, float] | None = None,
) -> dict[str, Any]:
    """The flat piece `rest` ((n, 2), metres) put on `place` (a `body_places` dict): its
    vertical ("vertical"), longest ("longest"; the default on arms and legs) or shortest
    ("shortest": a band whose length goes round) direction along the place's axis, `side`
    "centre", "left" or "right" of the centre line (a half's inner edge on it), turned `around_deg` about the axis, `clearance` metres off the body and rolled round
    the axis with the isometric bend. `grain` (the piece's grain line's direction): a torso or
    waist piece whose grain lies within 30 degrees of the pattern's x was laid on its side by a
    marker, and goes with its x along the body, narrower end first. Returns {"positions": (n, 3),
    "radius", "bend"}."""

def suggest_place(name: str, shape: ArrayLike, place: str | None = None) -> dict[str, Any]:
    """Where a piece called `name` with 2D `shape` goes: {"place", "side", "around_deg",
    "along", "offset"}, the keywords of `place_on_body`. With `place` (the artist's choice): on
    that place, keeping the suggestion's turn round the axis; a limb takes the longest direction
    and no half side, a band the shortest."""

def suggest_places(names: Sequence[str], shapes: Sequence[ArrayLike]) -> list[dict[str, Any]]:
    """`suggest_place` for every piece of a pattern, the words all the names start with (the
    style's name, as `ORILEG WB` in `ORILEG WB LL R`) left out before the names are read, numbered
    panels spread round their place, a cuff's `offset` the length of its sleeve."""

class WeldedMesh:
    """Sewn pieces merged into one mesh (`weld`, `Garment.welded`)."""

    positions: F32
    triangles: npt.NDArray[np.uint32]
    vertex_map: npt.NDArray[np.uint32]
    triangle_source: npt.NDArray[np.uint32]
    corner_weights: F32
    num_vertices: int
    stats: dict[str, int]
    def apply(self, frame: ArrayLike) -> F32: ...
    def apply_corners(self, values: ArrayLike) -> F32: ...

def weld(positions: ArrayLike, triangles_: ArrayLike, seams: Sequence[dict[str, Any]]) -> WeldedMesh: ...
