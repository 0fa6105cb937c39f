"""`audio`: a real WAV file (written here with soundfile) followed in step with the source feeds
`audio.level` bindings and audioFFT inputs; with no capture device the show goes on silent.

PortAudio capture itself cannot be tested here: there is no sound card in CI (a mock would
test nothing of it); `CaptureSound` shares its window/level/spectrum code with `FileSound`."""
import numpy as np
import pytest

from effects.audio import Audio
from effects.isf import Isf
from host.audio import CaptureSound, FileSound, Playback
from host.errors import UserError
from tests.host.render.stage import frames_with_hand, requires_gl, run_show

soundfile = pytest.importorskip("soundfile", reason="the audio extra: pip install 'issv[audio]'")
RATE = 44100
HAND = (-300.0, 200.0, 2000.0)
METER = """/*{"INPUTS": [{"NAME": "level", "TYPE": "float"}, {"NAME": "spectrum", "TYPE": "audioFFT", "MAX": 512}]}*/
void main() {
    float at_1k = IMG_NORM_PIXEL(spectrum, vec2((1000.0 / 22050.0) * (511.0 / 512.0) + 0.5 / 512.0, 0.5)).r;
    float at_5k = IMG_NORM_PIXEL(spectrum, vec2(5000.0 / 22050.0, 0.5)).r;
    gl_FragColor = vec4(level, at_1k, at_5k, 1.0);
}
"""


def wav(tmp_path, tone_from: float, seconds: float = 2.0):
    """A 1 kHz sine at amplitude 0.5 from `tone_from` seconds on, silence before."""
    t = np.arange(int(RATE * seconds)) / RATE
    samples = np.where(t >= tone_from, 0.5 * np.sin(2 * np.pi * 1000 * t), 0.0).astype(np.float32)
    path = tmp_path / "tone.wav"
    soundfile.write(str(path), samples, RATE)
    return path


def test_a_file_gives_level_and_spectrum_where_the_source_is(tmp_path):
    sound = FileSound(wav(tmp_path, tone_from=1.0))
    sound.seek(0.5)
    assert sound.level() == 0.0
    sound.seek(1.5)
    assert sound.level() == pytest.approx(0.5 / np.sqrt(2), rel=0.02)
    spectrum = sound.spectrum(512)
    assert np.argmax(spectrum) == round(1000 / (RATE / 2) * 512)
    assert spectrum.max() == pytest.approx(0.5, rel=0.1)


@requires_gl
@pytest.mark.parametrize("tone_from, lit", [(0.0, True), (1.0, False)])
def test_isf_inputs_hear_the_file_in_step_with_the_frames(tmp_path, tone_from, lit):
    shader = tmp_path / "meter.fs"
    shader.write_text(METER)
    effects = [Audio(Audio.Options(file=str(wav(tmp_path, tone_from)))),
               Isf(Isf.Options(file=str(shader), bind={"level": "audio.level"}))]
    image = run_show(effects, frames_with_hand([HAND] * 6), tmp_path, (64, 48))[0]  # frames at 0 .. 0.17 s
    b, g, r = (int(v) for v in image[24, 32])
    if lit:
        assert abs(r - 0.354 * 255) <= 6 and g > 80 and b < 10
    else:
        assert (r, g, b) == (0, 0, 0)  # the tone starts at 1 s: the show is not there yet


def test_a_file_that_is_not_sound_is_one_clear_error(tmp_path):
    bad = tmp_path / "bad.wav"
    bad.write_text("not a wav")
    with pytest.raises(UserError, match=r"audio: cannot read .*bad\.wav"):
        FileSound(bad)


@requires_gl
def test_no_capture_device_says_so_once_and_the_show_goes_on_silent(tmp_path, capsys):
    try:
        CaptureSound().close()
        pytest.skip("this machine has a capture device")
    except UserError:
        pass
    shader = tmp_path / "meter.fs"
    shader.write_text(METER)
    effects = [Audio(Audio.Options()), Isf(Isf.Options(file=str(shader), bind={"level": "audio.level"}))]
    image, show, _ = run_show(effects, frames_with_hand([HAND] * 3), tmp_path, (64, 48))
    err = capsys.readouterr().err
    assert err.count("the show goes on silent") == 1 and "audio:" in err
    assert all(slot.enabled for slot in show.effects)
    assert image[24, 32].max() == 0  # silence: level 0, an empty spectrum


@requires_gl
def test_a_file_with_no_playback_device_is_not_heard_but_still_drives_the_effects(tmp_path, capsys):
    try:
        Playback(FileSound(wav(tmp_path, 0.0))).close()
        pytest.skip("this machine has a playback device: the file is heard")
    except UserError:
        pass
    shader = tmp_path / "meter.fs"
    shader.write_text(METER)
    path = wav(tmp_path, 0.0)
    effects = [Audio(Audio.Options(file=str(path))), Isf(Isf.Options(file=str(shader), bind={"level": "audio.level"}))]
    image = run_show(effects, frames_with_hand([HAND] * 3), tmp_path, (64, 48))[0]
    err = capsys.readouterr().err
    assert err.count("audio: no playback device") == 1 and f"{path} drives the effects but is not heard" in err
    assert image[24, 32, 2] > 60  # the level still reaches the shader


def test_the_play_head_runs_on_by_itself_and_jumps_when_the_source_moves_away(tmp_path):
    """The device callback's logic, called as PortAudio would (no stream is opened: no device here)."""
    sound = FileSound(wav(tmp_path, 0.0))
    player = Playback.__new__(Playback)
    player.sound, player.head = sound, 0
    out = np.empty((441, 1), np.float32)
    sound.seek(0.005)  # the source moved less than RESYNC_S: the head plays on from where it was
    player._callback(out, 441, None, None)
    assert player.head == 441 and np.array_equal(out, sound.data[:441])
    sound.seek(1.0)  # a loop or a skip: the head jumps to the source
    player._callback(out, 441, None, None)
    assert player.head == RATE + 441 and np.array_equal(out, sound.data[RATE:RATE + 441])
    sound.seek(sound.duration)  # past the end: silence, not an error
    player.head = len(sound.data) - 10
    player._callback(out, 441, None, None)
    assert np.array_equal(out[:10], sound.data[-10:]) and not out[10:].any()
