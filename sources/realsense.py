"""`realsense`: Intel RealSense cameras (D4xx, SR305, L515) and their `.bag` recordings, via pyrealsense2.

`pip install 'issv[realsense]'`. Live: the camera with `serial`, else the first found, streaming
depth at `width` x `height` @ `fps` (unset: 640x480 @ 30). The depth scale and the stream's
intrinsics are read from the device (from the file for a `.bag`), so millimetres are exact on
every model: a 1 mm scale (D4xx default) passes the camera's values through untouched, any other
(SR305 0.125 mm, L515 0.25 mm) is converted by a lookup table. The camera's own post-processing
filters are optional, applied in the order librealsense recommends (decimation, to disparity,
spatial, temporal, back to depth, hole filling); intrinsics follow decimation.

`path` plays a recording instead: `.bag` (what the RealSense Viewer and `rs-record` of
librealsense <= 2.57 write; the extra pins that range so `issv` and the tests write the same
format) or `.db3` (librealsense >= 2.58). `seek` starts later, `loop` repeats, `realtime = false`
plays as fast as the show reads.

Needs a camera plugged in (untested here): the live branch of `connect()` (serial selection,
width/height/fps on a device), `devices()` on real hardware, and unplug/reconnect on real USB.
The filters, scales and playback are tested on `.bag` files written by librealsense's own
software device and recorder.
"""
from __future__ import annotations

import datetime
import gc
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from host import DeviceInfo, Intrinsics
from host.errors import UserError
from host.options import ProfilePath
from sources import usb
from sources.depth_images import mm_table
from sources.live import EndOfStream, Grabbed, LiveCamera

INSTALL = "pip install 'issv[realsense]'"
POLL_MS = 100  # how long one wait for a frame lasts while checking whether a recording ended
INTEL = "8086"
REALSENSE_IDS = {(INTEL, pid): name for pid, name in {
    "0ad3": "RealSense D415", "0b07": "RealSense D435", "0b3a": "RealSense D435i", "0b5c": "RealSense D455",
    "0b5b": "RealSense D405", "0b64": "RealSense L515", "0b48": "RealSense SR305", "0aa5": "RealSense SR300",
    "0b4d": "RealSense D456", "0b6b": "RealSense D457"}.items()}


class RealSenseOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    serial: str | None = Field(None, description="the camera's serial number (unset: the first found)")
    path: ProfilePath | None = Field(None, description="play a recording (.bag or .db3) instead of a camera")
    width: int | None = Field(None, gt=0, description="depth width (unset: 640, or the recording's)")
    height: int | None = Field(None, gt=0, description="depth height (unset: 480, or the recording's)")
    fps: int | None = Field(None, gt=0, le=300, description="depth frame rate (unset: 30, or the recording's)")
    decimation: int = Field(1, ge=1, le=8, description="librealsense decimation filter: 1 = off, 2-8 = factor")
    spatial: bool = Field(False, description="librealsense spatial (edge-preserving) filter")
    temporal: bool = Field(False, description="librealsense temporal filter")
    hole_filling: bool = Field(False, description="librealsense hole-filling filter")
    seek: float = Field(0.0, ge=0, description="recording: start this many seconds in")
    loop: bool = Field(False, description="recording: start again at its end")
    realtime: bool = Field(True, description="recording: at its recorded pace (false: as fast as the show reads)")


def recording_seconds(rs, path: Path) -> float | None:
    """The recording's length, read without starting a pipeline (librealsense can abort when a
    pipeline is stopped right after it starts); None when librealsense cannot read the file (the
    pipeline then says why)."""
    context = rs.context()
    try:
        device = context.load_device(str(path))
    except RuntimeError:
        return None
    try:
        return device.get_duration().total_seconds()
    finally:
        context.unload_device(str(path))


def _info(rs, device, what) -> str:
    return device.get_info(what) if device.supports(what) else ""


def depth_modes(rs, device) -> tuple[str, ...]:
    """The depth stream's resolutions and rates, e.g. `848x480 @ 90 fps`."""
    modes = set()
    for sensor in device.query_sensors():
        for p in sensor.get_stream_profiles():
            if p.stream_type() == rs.stream.depth and p.format() == rs.format.z16:
                v = p.as_video_stream_profile()
                modes.add((v.width(), v.height(), p.fps()))
    return tuple(f"{w}x{h} @ {fps} fps" for w, h, fps in sorted(modes, reverse=True))


class RealSenseSource(LiveCamera):
    name = "realsense"
    Options = RealSenseOptions

    @classmethod
    def availability(cls) -> str | None:
        try:
            import pyrealsense2  # noqa: F401
        except ImportError:
            return f"the PyPI package `pyrealsense2` is missing: {INSTALL}"
        return None

    @classmethod
    def devices(cls) -> list[DeviceInfo]:
        """Cameras librealsense can open, and those on USB it cannot (with the udev rule to add)."""
        import pyrealsense2 as rs

        found, serials = [], set()
        for device in rs.context().query_devices():
            serial = _info(rs, device, rs.camera_info.serial_number)
            serials.add(serial)
            found.append(DeviceInfo(_info(rs, device, rs.camera_info.name), serial,
                                    _info(rs, device, rs.camera_info.firmware_version), depth_modes(rs, device)))
        for d in usb.find(REALSENSE_IDS):
            if d.serial not in serials:  # on USB, yet librealsense could not open it
                found.append(DeviceInfo(d.model, d.serial, d.firmware, (), usb.permission_problem([d]) or
                                        "librealsense cannot open it (in use by another program?)"))
        return found

    def connect(self) -> None:
        import pyrealsense2 as rs

        self._rs, o = rs, self.options
        config = rs.config()
        if o.path is not None:
            path = Path(o.path)
            if not path.is_file():
                raise UserError(f"{path}: no such RealSense recording (.bag)")
            length = recording_seconds(rs, path)
            if length is not None and o.seek > length:  # said before a pipeline starts and stops at once
                raise UserError(f"{path}: seek = {o.seek:g} s is past the recording's end ({length:.2f} s)")
            config.enable_device_from_file(str(path), repeat_playback=o.loop)
        elif o.serial:
            config.enable_device(o.serial)  # needs a camera plugged in
        if o.path is None or (o.width or o.height or o.fps):
            config.enable_stream(rs.stream.depth, o.width or 640, o.height or 480, rs.format.z16, o.fps or 30)
        else:
            config.enable_stream(rs.stream.depth)  # the recording's own depth stream
        self._pipeline = rs.pipeline()
        try:
            profile = self._pipeline.start(config)
        except RuntimeError as error:
            raise UserError(f"source 'realsense': {self._why_not(error)}") from None
        device = profile.get_device()
        self._playback = device.as_playback() if o.path is not None else None
        if self._playback is not None:
            self._playback.set_real_time(o.realtime)
            if o.seek:
                self._seek(o.seek)
        stream = profile.get_stream(rs.stream.depth).as_video_stream_profile()
        self.fps = float(stream.fps())
        # The scale is a float32 (0.001 m reads 0.0010000000474974513): its 6 digits are the meant value.
        self.depth_unit_mm = float(f"{device.first_depth_sensor().get_depth_scale() * 1000.0:.6g}")
        self._table = mm_table(self.depth_unit_mm)
        self._filters = self._make_filters()
        self._intrinsics_of: dict = {}
        self.width, self.height = stream.width() // o.decimation, stream.height() // o.decimation
        self.intrinsics = self._intrinsics(stream)
        self._last_number, self._last_ms, self._offset_ms = None, None, 0.0

    def _seek(self, seconds: float) -> None:
        """Seek with the player paused, then drop what it queued before the seek (the pipeline
        starts playing at once, so the file's first frames may already be waiting)."""
        self._playback.pause()
        self._playback.seek(datetime.timedelta(seconds=seconds))
        time.sleep(POLL_MS / 1000)  # a frame read before the pause reaches the queue
        while self._pipeline.poll_for_frames():
            pass
        self._playback.resume()

    def _why_not(self, error: RuntimeError) -> str:
        o = self.options
        if o.path is not None and (o.width or o.height or o.fps):
            return (f"{o.path}: no depth stream at {o.width or 640}x{o.height or 480} @ {o.fps or 30} fps in it "
                    f"({error}); leave width, height and fps unset to play the recording's own")
        if o.path is not None:
            return f"{o.path}: librealsense cannot play it: {error}"
        wanted = f"serial {self.options.serial}" if self.options.serial else "any RealSense"
        problem = usb.permission_problem(usb.find(REALSENSE_IDS))
        return problem or f"cannot start {wanted} (is it plugged in, on USB 3?): {error}"

    def _make_filters(self) -> list:
        rs, o = self._rs, self.options
        chain = []
        if o.decimation > 1:
            decimation = rs.decimation_filter()
            decimation.set_option(rs.option.filter_magnitude, o.decimation)
            chain.append(decimation)
        if o.spatial or o.temporal:
            chain.append(rs.disparity_transform(True))
            chain += [rs.spatial_filter()] if o.spatial else []
            chain += [rs.temporal_filter()] if o.temporal else []
            chain.append(rs.disparity_transform(False))
        if o.hole_filling:
            chain.append(rs.hole_filling_filter())
        return chain

    def _intrinsics(self, stream) -> Intrinsics:
        """The stream's intrinsics as librealsense reports them (cached per stream profile)."""
        key = (stream.unique_id(), stream.width(), stream.height())
        if key not in self._intrinsics_of:
            k = stream.get_intrinsics()
            self._intrinsics_of[key] = Intrinsics(k.fx, k.fy, k.ppx, k.ppy)
        return self._intrinsics_of[key]

    def grab(self, timeout: float) -> Grabbed | None:
        waited = 0.0
        while True:
            ok, frames = self._pipeline.try_wait_for_frames(POLL_MS)
            if ok:
                received = time.perf_counter()
                break
            if self._playback is not None and self._playback.current_status() == self._rs.playback_status.stopped:
                raise EndOfStream
            waited += POLL_MS / 1000
            if waited >= timeout:
                return None
        frame = frames.get_depth_frame()
        number, ms = frame.get_frame_number(), frame.get_timestamp()
        for f in self._filters:
            frame = f.process(frame)
        stream = frame.get_profile().as_video_stream_profile()
        self.intrinsics = self._intrinsics(stream)
        raw = np.asanyarray(frame.get_data())
        depth = raw.copy() if self._table is None else np.take(self._table, raw)
        skipped = 0
        if self._last_number is not None and number > self._last_number:
            skipped = number - self._last_number - 1
        if self._last_ms is not None and ms + self._offset_ms <= self._last_ms:  # a loop started again
            self._offset_ms = self._last_ms + 1000.0 / self.fps - ms
        self._last_number, self._last_ms = number, ms + self._offset_ms
        return Grabbed(depth, self._last_ms / 1000.0, skipped, received)

    def disconnect(self) -> None:
        pipeline = getattr(self, "_pipeline", None)
        if pipeline is not None:
            self._pipeline = None
            playback, self._playback = self._playback, None
            if playback is not None:
                # The player's thread can still be handing a frame to the pipeline after stop(), and
                # the pipeline then crashes as it is freed (gdb: frame_callback::on_frame against
                # ~pipeline, 1 close in about 150 on a busy machine): pause it first, so no frame is in flight.
                playback.pause()
            pipeline.stop()


def write_bag(path: Path, frames: list[np.ndarray], intrinsics: Intrinsics, fps: int,
              depth_units_m: float = 0.001, pace: bool = False) -> None:
    """Record depth images (raw counts) into a .bag through librealsense's own software device
    and recorder: the library's real file format, for tests and benches without a camera.
    `pace` pushes them at `fps` in real time (the recorder stamps frames with the wall clock).

    The recording runs in a child Python: pyrealsense2's `software_video_frame.pixels` has a
    memory-ownership bug (librealsense issue #14751, a double free) that corrupted the heap of a
    long pytest process here (wrong pixels, then a segfault); a child takes it down with it."""
    with tempfile.TemporaryDirectory(prefix="issv-bag-") as tmp:
        job = Path(tmp) / "frames.npz"
        np.savez(job, frames=np.stack(frames), intrinsics=intrinsics.as_list(), fps=fps,
                 depth_units_m=depth_units_m, pace=pace)
        here = str(Path(__file__).resolve().parents[1])
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [here, os.environ.get("PYTHONPATH")]))}
        done = subprocess.run([sys.executable, "-c", "import sys; from sources.realsense import _record_bag; "
                               "_record_bag(*sys.argv[1:])", str(path), str(job)],
                              capture_output=True, text=True, env=env, timeout=300)
    if done.returncode != 0:
        raise RuntimeError(f"{path}: recording through librealsense's software device failed "
                           f"(exit code {done.returncode}): {done.stderr[-500:]}")


def _record_bag(path: str, job: str) -> None:
    """The child's side of write_bag: the frames and settings come in an .npz."""
    import pyrealsense2 as rs

    with np.load(job) as z:
        frames, intrinsics, fps = list(z["frames"]), [float(v) for v in z["intrinsics"]], int(z["fps"])
        depth_units_m, pace = float(z["depth_units_m"]), bool(z["pace"])
    h, w = frames[0].shape
    device = rs.software_device()
    device.register_info(rs.camera_info.name, "issv software depth camera")
    device.register_info(rs.camera_info.serial_number, "000000000001")
    sensor = device.add_sensor("Stereo Module")
    sensor.add_read_only_option(rs.option.depth_units, depth_units_m)
    k = rs.intrinsics()
    k.width, k.height, k.fx, k.fy, k.ppx, k.ppy = w, h, *intrinsics
    k.model, k.coeffs = rs.distortion.brown_conrady, [0.0] * 5
    stream = rs.video_stream()
    stream.type, stream.index, stream.uid, stream.width, stream.height = rs.stream.depth, 0, 0, w, h
    stream.fps, stream.bpp, stream.fmt, stream.intrinsics = fps, 2, rs.format.z16, k
    profile = sensor.add_video_stream(stream).as_video_stream_profile()
    recorder = rs.recorder(path, device)
    recording = recorder.query_sensors()[0]
    queue = rs.frame_queue(len(frames) + 1)
    recording.open(recording.get_stream_profiles()[0])
    recording.start(queue)
    for i, pixels in enumerate(frames):
        f = rs.software_video_frame()
        f.pixels, f.stride, f.bpp, f.frame_number = np.ascontiguousarray(pixels, np.uint16), w * 2, 2, i
        f.timestamp, f.domain = 5000.0 + i * 1000.0 / fps, rs.timestamp_domain.hardware_clock
        f.profile, f.depth_units = profile, depth_units_m
        sensor.on_video_frame(f)
        if not queue.wait_for_frame(1000):
            raise RuntimeError(f"{path}: librealsense's recorder did not take frame {i}")
        if pace:
            time.sleep(1.0 / fps)
    recording.stop()
    recording.close()
    del recording, recorder, queue  # the recorder writes the file's index when it is released
    gc.collect()
