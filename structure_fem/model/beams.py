"""Continuum reference: a cantilever of beam elements under its own weight (SI units).

The thesis's Eq. 7.1 treats a line of robots as one continuous beam,
``delta = W L^4 / (8 E I)`` with ``W = A rho g``. :func:`cantilever_tip` solves
the same beam with exudyn ANCF cable elements (``ObjectANCFCable2D``), so the
package's beam model is validated against Eq. 7.1, and :func:`eq71_tip` gives
the closed form itself for a line of robots (hollow robots: the section's
``A`` and ``I`` both scale with the fill fraction, which cancels).
"""

from __future__ import annotations

import math

from cubot_cad.properties import RobotProperties
from structure_fem.errors import InputError, SolverFailure
from structure_fem.model.structures import GRAVITY


def eq71_tip(length_m: float, width_m: float, height_m: float, density_kg_m3: float, youngs_pa: float) -> float:
    """Thesis Eq. 7.1: tip deflection (m) of a solid rectangular cantilever under its own weight."""
    for name, v in (("length", length_m), ("width", width_m), ("height", height_m),
                    ("density", density_kg_m3), ("Young's modulus", youngs_pa)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"beam {name} must be > 0, got {v!r}")
    w = width_m * height_m * density_kg_m3 * GRAVITY
    i = width_m * height_m ** 3 / 12.0
    return w * length_m ** 4 / (8.0 * youngs_pa * i)


def eq71_line_tip(robot: RobotProperties, widths: int) -> float:
    """Eq. 7.1 for a line of ``robot`` cantilevered ``widths`` robot lengths (the continuum estimate)."""
    return eq71_tip(widths * robot.length_m, robot.width_m, robot.height_m, robot.density_kg_m3,
                    robot.youngs_modulus_pa)


def cantilever_tip(length_m: float, mass_per_length: float, bending_stiffness: float,
                   axial_stiffness: float, elements: int = 16) -> float:
    """Tip deflection (m, positive down) of a clamped ANCF cable cantilever under gravity."""
    import exudyn as exu
    from exudyn.itemInterface import (
        LoadMassProportional,
        MarkerBodyMass,
        NodePoint2DSlope1,
        ObjectANCFCable2D,
    )

    for name, v in (("length", length_m), ("mass per length", mass_per_length),
                    ("bending stiffness", bending_stiffness), ("axial stiffness", axial_stiffness)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"beam {name} must be > 0, got {v!r}")
    if not (isinstance(elements, int) and elements >= 1):
        raise InputError(f"beam elements must be an integer >= 1, got {elements!r}")
    exu.config.printToConsole = False
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    le = length_m / elements
    nodes = [mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[i * le, 0.0, 1.0, 0.0]))
             for i in range(elements + 1)]
    for i in range(elements):
        o = mbs.AddObject(ObjectANCFCable2D(nodeNumbers=[nodes[i], nodes[i + 1]], length=le,
                                            massPerLength=mass_per_length, bendingStiffness=bending_stiffness,
                                            axialStiffness=axial_stiffness))
        m = mbs.AddMarker(MarkerBodyMass(bodyNumber=o))
        mbs.AddLoad(LoadMassProportional(markerNumber=m, loadVector=[0.0, -GRAVITY, 0.0]))
    q = _clamp_root_and_solve(exu, mbs, nodes[0], load_steps=4,
                              what=f"beam cantilever L={length_m} m, {elements} elements")
    return -float(q[4 * elements + 1])


def flexible_line_tip(robot: RobotProperties, joint_nm_per_rad: float, robots_over: int,
                      elements_per_robot: int = 4, joint_length_m: float = 0.002) -> float:
    """Tip deflection (m) of ``robots_over`` robots cantilevered from a clamped edge, every robot
    a flexible beam (ANCF cable elements, ``E I`` of :func:`structure_fem.model.bodies.body_bending`, the
    CAD's section, as the lumped model's) and every coupling a short element of length
    ``joint_length_m`` whose bending stiffness ``k * l`` makes it a rotational spring ``k``.

    The beam-element counterpart of ``solve(..., flexible=True)`` (which lumps the robots'
    bending at the joints), without backlash.
    """
    import exudyn as exu
    from exudyn.itemInterface import (
        LoadMassProportional,
        MarkerBodyMass,
        NodePoint2DSlope1,
        ObjectANCFCable2D,
    )

    if not (math.isfinite(joint_nm_per_rad) and joint_nm_per_rad > 0):
        raise InputError(f"joint stiffness must be > 0 N m/rad, got {joint_nm_per_rad!r}")
    if not (isinstance(robots_over, int) and robots_over >= 1):
        raise InputError(f"robots over the edge must be an integer >= 1, got {robots_over!r}")
    from structure_fem.model.bodies import body_bending

    fill = min(1.0, robot.mass_kg / (robot.density_kg_m3 * robot.length_m * robot.width_m * robot.height_m))
    ei = body_bending(robot).flexural_rigidity_n_m2  # the same E I as the lumped model's
    ea = robot.youngs_modulus_pa * fill * robot.width_m * robot.height_m  # axial: barely matters in bending
    mu = robot.mass_kg / robot.length_m
    # Segments from the clamp outwards: joint at the edge, then robot, joint, robot, ...
    segs: list[tuple[float, float]] = []  # (length, bending stiffness)
    body = robot.length_m - joint_length_m
    for _ in range(robots_over):
        segs.append((joint_length_m, joint_nm_per_rad * joint_length_m))
        segs += [(body / elements_per_robot, ei)] * elements_per_robot
    exu.config.printToConsole = False
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    x = 0.0
    nodes = [mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[0.0, 0.0, 1.0, 0.0]))]
    for le, eib in segs:
        x += le
        nodes.append(mbs.AddNode(NodePoint2DSlope1(referenceCoordinates=[x, 0.0, 1.0, 0.0])))
        o = mbs.AddObject(ObjectANCFCable2D(nodeNumbers=[nodes[-2], nodes[-1]], length=le, massPerLength=mu,
                                            bendingStiffness=eib, axialStiffness=ea))
        m = mbs.AddMarker(MarkerBodyMass(bodyNumber=o))
        mbs.AddLoad(LoadMassProportional(markerNumber=m, loadVector=[0.0, -GRAVITY, 0.0]))
    q = _clamp_root_and_solve(exu, mbs, nodes[0], load_steps=8,
                              what=f"flexible line of {robots_over} robots")
    return -float(q[4 * len(segs) + 1])


def _clamp_root_and_solve(exu, mbs, root_node: int, load_steps: int, what: str):
    """Clamp the root node (x, y and the slope's y component), solve statically, return the
    ODE2 coordinates (m). Settings per the toolchain notes; relative tolerance 1e-6 sits above
    the round-off floor (~3e-8 with EA ~ 1e8 N). Non-convergence raises SolverFailure naming
    ``what``."""
    from exudyn.itemInterface import (
        MarkerNodeCoordinate,
        NodePointGround,
        ObjectConnectorCoordinate,
    )

    g = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    mg = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=g, coordinate=0))
    for coord in (0, 1, 3):
        mc = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=root_node, coordinate=coord))
        mbs.AddObject(ObjectConnectorCoordinate(markerNumbers=[mg, mc]))
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.solution.file.write = False
    ss.solution.sensors.active = False
    st = ss.staticSolver
    st.verboseMode = 0
    st.numberOfLoadSteps = load_steps
    st.newton.adaptInitialResidual = False
    st.newton.relativeTolerance = 1e-6
    st.newton.absoluteTolerance = 1e-6
    ss.linearSolver.solverType = exu.LinearSolverType.EXUdense
    try:
        ok = mbs.SolveStatic(ss)
    except Exception as exc:
        raise SolverFailure(f"{what}: {exc}") from exc
    if ok is False:
        raise SolverFailure(f"{what} did not converge")
    return mbs.systemData.GetODE2Coordinates()
