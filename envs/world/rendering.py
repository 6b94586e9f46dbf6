"""Offscreen, headless rendering: the OpenGL context, the panorama and the top-down view.

All cameras of the ring are drawn into one offscreen framebuffer side by side, read back at once
and unwrapped with precomputed ``cv2.remap`` tables. Pixels are read and remapped as RGBA, the
framebuffer's own layout, and the alpha dropped last: Mesa copies RGBA rows as they are but
converts RGB pixel by pixel, and OpenCV remaps four channels in half the time of three.

In Mesa's software renderer every drawn geom costs CPU and rasterization whether or not it ends
up on screen, so each camera draws only the static geoms whose bounding sphere meets its view
frustum, planes that face it and, given the floor plan, what the doorways leave in view
(:mod:`envs.world.portals`): before each camera's scene update, the others are moved to a hidden
geom group (``mjv_updateScene`` reads ``model.geom_group`` every call and costs ~2 µs). The tests
are conservative, so the picture is the same as without culling
(``tests/envs/world/test_rendering.py``).

``MUJOCO_GL`` must be set before ``mujoco`` is first imported; :mod:`envs` sets it to ``egl``
unless the user chose a backend.
"""

from __future__ import annotations

import math
import os

import cv2
import mujoco
import numpy as np

from .layout import FloorPlan
from .panorama import PanoramaGeometry
from .portals import PortalCuller, box_corners
from .scene import CORE_GROUP, HIDDEN_GROUP


def gl_context(width: int, height: int) -> mujoco.GLContext:
    """A current offscreen GL context, or a ``RuntimeError`` that says how to get one."""
    backend = os.environ.get("MUJOCO_GL", "<unset>")
    try:
        ctx = mujoco.GLContext(width, height)
        ctx.make_current()
    except Exception as exc:  # GL failures surface as several unrelated exception types
        raise RuntimeError(
            f"could not create an offscreen OpenGL context with MUJOCO_GL={backend}: {exc}. "
            "On a headless machine use MUJOCO_GL=egl (Mesa's libEGL, e.g. Debian's libegl1 and "
            "libgl1-mesa-dri) and import envs before mujoco."
        ) from exc
    return ctx


def _read_rgba(ctx: mujoco.MjrContext, out: np.ndarray) -> np.ndarray:
    """Read the offscreen framebuffer's lower-left ``out.shape[:2]`` pixels into the RGBA
    uint8 array ``out`` (bottom row first), as ``mjr_readPixels`` reads RGB."""
    from OpenGL import GL  # PyOpenGL comes with mujoco

    GL.glBindFramebuffer(GL.GL_READ_FRAMEBUFFER, ctx.offFBO)
    GL.glReadBuffer(GL.GL_COLOR_ATTACHMENT0)
    GL.glReadPixels(0, 0, out.shape[1], out.shape[0], GL.GL_RGBA, GL.GL_UNSIGNED_BYTE, out)
    return out


def _cheaper_texture_filtering(ctx: mujoco.MjrContext) -> None:
    """Sample one mipmap level instead of blending two (MuJoCo's trilinear default).

    Measured on llvmpipe: ~10% less render time for a mean difference of 0.5/255 per pixel.
    """
    from OpenGL import GL  # PyOpenGL comes with mujoco

    for i in range(ctx.ntexture):
        GL.glBindTexture(GL.GL_TEXTURE_2D, int(ctx.texture[i]))
        GL.glTexParameteri(GL.GL_TEXTURE_2D, GL.GL_TEXTURE_MIN_FILTER, GL.GL_LINEAR_MIPMAP_NEAREST)
    GL.glBindTexture(GL.GL_TEXTURE_2D, 0)


class SceneRenderer:
    """Renders a model's panorama (robot cameras) and a top-down overview offscreen.

    Args:
        model: the compiled model; its offscreen buffer size is enlarged if needed.
        camera_names: the ring of cameras, in yaw order, as made by :mod:`envs.world.scene`.
        geometry: panorama size and remap tables; must match how the cameras were built.
        overview_size: (height, width) of :meth:`top_down` images.
        plan, geom_rooms: the floor plan and the rooms of each geom (``Scene.geom_rooms``);
            given both, the cameras skip the geoms that no doorway leaves in view.
        cull: skip the geoms a camera cannot see (the default); ``False`` draws them all, the
            same picture more slowly (the tests compare the two).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        camera_names: tuple[str, ...],
        geometry: PanoramaGeometry,
        overview_size: tuple[int, int] = (480, 480),
        plan: FloorPlan | None = None,
        geom_rooms: dict[str, tuple[int, ...]] | None = None,
        cull: bool = True,
    ) -> None:
        if len(camera_names) != geometry.n_cameras:
            raise ValueError(f"{len(camera_names)} cameras for a {geometry.n_cameras}-camera ring")
        self.model = model
        self.geometry = geometry
        strip_h, strip_w = geometry.strip_shape
        buf_w = max(strip_w, overview_size[1])
        buf_h = max(strip_h, overview_size[0])
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, buf_w)
        model.vis.global_.offheight = max(model.vis.global_.offheight, buf_h)
        self._gl = gl_context(buf_w, buf_h)
        self._ctx = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_100)
        _cheaper_texture_filtering(self._ctx)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._ctx)
        self._scene = mujoco.MjvScene(model, maxgeom=max(1000, 2 * model.ngeom))
        self._option = mujoco.MjvOption()
        self._option.geomgroup[HIDDEN_GROUP] = 0
        self._option.geomgroup[CORE_GROUP] = 0  # hidden by the linings; caps stand in at doors
        # the robot's own rangefinder rays and sites are sensors, not scenery: a camera must not
        # see them (nor draw them: each of the 17 tiny site spheres is hundreds of triangles)
        self._option.flags[mujoco.mjtVisFlag.mjVIS_RANGEFINDER] = 0
        self._option.sitegroup[:] = 0
        self._top_option = mujoco.MjvOption()  # the top-down view for people shows the rays
        self._top_option.geomgroup[HIDDEN_GROUP] = 0
        self._perturb = mujoco.MjvPerturb()
        self._camera = mujoco.MjvCamera()
        self._camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
        self._camera_ids = [model.camera(n).id for n in camera_names]
        # one interleaved float map: the same pixels as two planar ones, a third faster
        self._map_xy = np.dstack(geometry.remap_tables())
        self._culling = cull
        self._init_culling(plan, geom_rooms)
        self._strip = np.empty((strip_h, strip_w, 4), np.uint8)
        self._overview = np.empty((*overview_size, 3), np.uint8)

    def _init_culling(self, plan: FloorPlan | None,
                      geom_rooms: dict[str, tuple[int, ...]] | None) -> None:
        m, g = self.model, self.geometry
        data = mujoco.MjData(m)
        mujoco.mj_kinematics(m, data)
        static = m.geom_bodyid == 0  # world geoms never move: their bounds are computed once
        size = m.geom_size
        radius = np.where(m.geom_type == mujoco.mjtGeom.mjGEOM_PLANE,
                          np.linalg.norm(size[:, :2], axis=1), np.linalg.norm(size, axis=1))
        infinite = (m.geom_type == mujoco.mjtGeom.mjGEOM_PLANE) & (radius == 0)
        self._cull = static & ~infinite
        self._centers = data.geom_xpos[self._cull].copy()
        self._radii = radius[self._cull]
        # a plane seen from behind is drawn half transparent; here every plane lines a room or
        # lies on its floor, so from behind it is hidden by the wall or jamb it backs onto
        plane = m.geom_type[self._cull] == mujoco.mjtGeom.mjGEOM_PLANE
        self._normals = np.where(plane[:, None],
                                 data.geom_xmat[self._cull].reshape(-1, 3, 3)[:, :, 2], 0.0)
        self._groups = m.geom_group.copy()
        # the robot never sees itself: its body is below the cameras' field of view
        robot_root = m.body_rootid[m.cam_bodyid[self._camera_ids[0]]]
        robot_geoms = m.body_rootid[m.geom_bodyid] == robot_root
        self._camera_groups = self._groups.copy()  # what every camera draws before culling
        self._camera_groups[robot_geoms] = HIDDEN_GROUP
        f = g.focal
        self._ring_half = (math.atan(g.cam_width / (2 * f)), math.atan(g.cam_height / (2 * f)))
        self._portals = None
        if plan is not None and geom_rooms is not None:
            ids = np.flatnonzero(self._cull)
            rooms = np.zeros((len(ids), len(plan.rooms)), bool)
            index = {int(i): k for k, i in enumerate(ids)}
            for name, owners in geom_rooms.items():
                rooms[index[m.geom(name).id], list(owners)] = True
            corners = box_corners(data.geom_xpos[ids], data.geom_xmat[ids], size[ids],
                                  m.geom_type[ids] == mujoco.mjtGeom.mjGEOM_PLANE)
            self._portals = PortalCuller(plan, corners, rooms)

    def _in_view(self, data: mujoco.MjData, cam_ids: list[int], half: tuple[float, float]
                 ) -> np.ndarray:
        """(cameras, culled geoms) bool: the geoms whose bounding sphere meets each camera's
        frustum (horizontal and vertical half-angles ``half``), planes that face it, and that
        the doorways leave in view of its position."""
        if not self._culling:
            return np.ones((len(cam_ids), len(self._centers)), bool)
        rel = self._centers[None, :, :] - data.cam_xpos[cam_ids][:, None, :]
        axes = data.cam_xmat[cam_ids].reshape(-1, 3, 3)  # columns: camera right, up, back
        proj = rel @ axes  # (cameras, geoms, 3): each centre in its camera's frame
        right, up, back = proj[..., 0], proj[..., 1], proj[..., 2]
        r = self._radii[None, :]
        sh, ch = math.sin(half[0]), math.cos(half[0])
        sv, cv = math.sin(half[1]), math.cos(half[1])
        seen = ((-back * sh - right * ch >= -r) & (-back * sh + right * ch >= -r)
                & (-back * sv - up * cv >= -r) & (-back * sv + up * cv >= -r)
                & (np.einsum("kgd,gd->kg", rel, self._normals) <= 0))  # planes facing the camera
        if self._portals is not None:
            walks: dict[tuple[float, float], np.ndarray] = {}  # the ring shares one mast
            for k, cam_id in enumerate(cam_ids):
                x, y = (float(v) for v in data.cam_xpos[cam_id, :2])
                if (x, y) not in walks:
                    walks[x, y] = self._portals.visible(x, y)
                seen[k] &= walks[x, y]
        return seen

    def _scene_for(self, data: mujoco.MjData, camera: mujoco.MjvCamera, shown: np.ndarray
                   ) -> None:
        """Fill the scene as ``camera`` sees it: of the cullable geoms those marked in ``shown``,
        and every other geom but the robot's own."""
        groups = self._camera_groups.copy()
        groups[self._cull] = np.where(shown, self._groups[self._cull], HIDDEN_GROUP)
        self.model.geom_group[:] = groups
        try:
            mujoco.mjv_updateScene(self.model, data, self._option, self._perturb, camera,
                                   mujoco.mjtCatBit.mjCAT_ALL, self._scene)
        finally:
            self.model.geom_group[:] = self._groups

    def panorama(self, data: mujoco.MjData) -> np.ndarray:
        """The (height, width, 3) uint8 panorama seen from the robot in ``data``."""
        self._gl.make_current()
        g = self.geometry
        shown = self._in_view(data, self._camera_ids, self._ring_half)
        for k, cam_id in enumerate(self._camera_ids):
            self._camera.fixedcamid = cam_id
            self._scene_for(data, self._camera, shown[k])
            rect = mujoco.MjrRect(k * g.cam_width, 0, g.cam_width, g.cam_height)
            mujoco.mjr_render(rect, self._scene, self._ctx)
        strip = _read_rgba(self._ctx, self._strip)
        # cv2's stubs want an array for map2; OpenCV takes None when map1 holds both coordinates
        pano = cv2.remap(strip, self._map_xy, None, cv2.INTER_LINEAR,  # type: ignore[call-overload]
                         borderMode=cv2.BORDER_REPLICATE)
        return cv2.cvtColor(pano, cv2.COLOR_RGBA2RGB)

    def perspective(self, data: mujoco.MjData, camera: str, width: int, height: int
                    ) -> np.ndarray:
        """The (height, width, 3) uint8 image of the model's camera ``camera``."""
        self._gl.make_current()
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FIXED
        cam.fixedcamid = self.model.camera(camera).id
        half_v = math.radians(self.model.cam_fovy[cam.fixedcamid]) / 2
        half = (math.atan(math.tan(half_v) * width / height), half_v)
        self._scene_for(data, cam, self._in_view(data, [cam.fixedcamid], half)[0])
        mujoco.mjr_render(mujoco.MjrRect(0, 0, width, height), self._scene, self._ctx)
        image = _read_rgba(self._ctx, np.empty((height, width, 4), np.uint8))
        return cv2.cvtColor(image[::-1], cv2.COLOR_RGBA2RGB)  # OpenGL reads the bottom row first

    def top_down(self, data: mujoco.MjData, bounds: tuple[float, float, float, float]
                 ) -> np.ndarray:
        """An orthographic view from above of the rectangle ``bounds`` = (x0, y0, x1, y1)."""
        self._gl.make_current()
        h, w = self._overview.shape[:2]
        x0, y0, x1, y1 = bounds
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.orthographic = 1
        cam.lookat[:] = [(x0 + x1) / 2, (y0 + y1) / 2, 0.0]
        cam.distance = 10.0
        cam.elevation = -90.0
        cam.azimuth = 90.0  # +x to the right, +y up in the picture
        self.model.vis.global_.orthographic = 1
        # orthographic fovy is the visible height in metres
        span = max(y1 - y0, (x1 - x0) * h / w) * 1.08
        saved = self.model.vis.global_.fovy
        self.model.vis.global_.fovy = span
        try:
            mujoco.mjv_updateScene(self.model, data, self._top_option, self._perturb, cam,
                                   mujoco.mjtCatBit.mjCAT_ALL, self._scene)
            rect = mujoco.MjrRect(0, 0, w, h)
            mujoco.mjr_render(rect, self._scene, self._ctx)
            mujoco.mjr_readPixels(self._overview, None, rect, self._ctx)
        finally:
            self.model.vis.global_.fovy = saved
            self.model.vis.global_.orthographic = 0
        return self._overview[::-1].copy()

    def close(self) -> None:
        """Free the GL resources; the renderer cannot be used afterwards."""
        if getattr(self, "_gl", None) is not None:
            # MjrContext.free deletes its textures, lists and framebuffers by name in the
            # *current* context: with another renderer's context current, it would delete that
            # renderer's objects, which share the names, and that env would go on returning its
            # last picture
            self._gl.make_current()
            self._ctx.free()
            self._gl.free()
            self._gl = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # interpreter shutdown may have torn GL down already
            pass
