"""The playback clock: wall-clock driven frames, speed, loop, step, seek and re-render."""

from __future__ import annotations

import math

import pytest

from animstudio.preview.playback import PlaybackClock


def test_paused_clock_stays_on_its_frame() -> None:
    clock = PlaybackClock(100, 30.0, now_s=0.0)
    assert clock.frame_at(10.0).frame == 0
    assert clock.next_frame_time(10.0) == math.inf


def test_playing_follows_wall_clock_at_fps_without_drift() -> None:
    clock = PlaybackClock(1000, 30.0, now_s=5.0)
    clock.play(5.0)
    # However irregularly the clock is asked, the frame is floor(elapsed * fps).
    for t in (0.0, 0.01, 0.5, 1.0 - 1e-6, 1.0, 3.3334, 10.0):
        assert clock.frame_at(5.0 + t).frame == math.floor(t * 30 + 1e-9)


def test_next_frame_time_is_the_next_frame_boundary() -> None:
    clock = PlaybackClock(100, 25.0, now_s=0.0)
    clock.play(0.0)
    assert clock.next_frame_time(0.01) == pytest.approx(0.04)
    assert clock.next_frame_time(0.05) == pytest.approx(0.08)


@pytest.mark.parametrize("speed", [0.25, 0.5, 2.0])
def test_speed_scales_the_frame_rate(speed: float) -> None:
    clock = PlaybackClock(10_000, 30.0, now_s=0.0)
    clock.play(0.0)
    clock.set_speed(speed, 0.0)
    assert clock.frame_at(4.0).frame == math.floor(4.0 * 30 * speed + 1e-9)


def test_speed_change_keeps_the_current_frame() -> None:
    clock = PlaybackClock(10_000, 30.0, now_s=0.0)
    clock.play(0.0)
    clock.set_speed(2.0, 1.0)  # at frame 30
    assert clock.frame_at(1.0).frame == 30
    assert clock.frame_at(2.0).frame == 90


@pytest.mark.parametrize("speed", [0.1, 2.5, 0.0])
def test_speed_out_of_range_is_refused(speed: float) -> None:
    clock = PlaybackClock(10, 30.0, now_s=0.0)
    with pytest.raises(ValueError, match="speed"):
        clock.set_speed(speed, 0.0)


def test_loop_wraps_and_no_loop_stops_on_the_last_frame() -> None:
    clock = PlaybackClock(30, 30.0, now_s=0.0)
    clock.play(0.0)
    assert clock.frame_at(1.5).frame == 15  # 45 frames played in a 30-frame clip
    clock.loop = False
    status = clock.frame_at(2.5)
    assert (status.frame, status.playing, status.finished) == (29, False, True)
    assert clock.frame_at(9.0).frame == 29
    clock.play(10.0)  # playing again after the end starts over
    assert clock.frame_at(10.5).frame == 15


def test_step_pauses_and_moves_one_frame() -> None:
    clock = PlaybackClock(10, 30.0, now_s=0.0)
    clock.play(0.0)
    assert clock.step(+1, 0.1) == 4  # frame 3 was showing
    assert not clock.playing
    assert clock.step(-1, 5.0) == 3
    assert clock.step(-5, 5.0) == 8  # looping wraps backwards
    clock.loop = False
    assert clock.step(+5, 5.0) == 9


def test_seek_clamps_into_the_clip() -> None:
    clock = PlaybackClock(50, 30.0, now_s=0.0)
    clock.seek(80, 0.0)
    assert clock.frame_at(0.0).frame == 49
    clock.seek(-3, 0.0)
    assert clock.frame_at(0.0).frame == 0


def test_retarget_keeps_the_frame_and_clamps_to_a_shorter_clip() -> None:
    clock = PlaybackClock(300, 30.0, now_s=0.0)
    clock.seek(120, 0.0)
    clock.retarget(200, 30.0, 1.0)
    assert clock.frame_at(1.0).frame == 120
    clock.retarget(100, 30.0, 1.0)
    assert clock.frame_at(1.0).frame == 99
    assert clock.num_frames == 100
