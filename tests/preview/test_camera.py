"""Camera follow: our own moves versus the user's."""

from __future__ import annotations

import numpy as np

from animstudio.preview.camera import CameraFollower

OFFSET = np.array([1.0, 0.5, -3.0])


def _ready() -> CameraFollower:
    follower = CameraFollower(OFFSET)
    assert follower.command(np.zeros(3)) is None  # no camera writes before the client reported
    assert follower.report(np.array([5.0, 5.0, 5.0]), np.zeros(3)) is False
    assert follower.ready
    return follower


def test_follow_keeps_the_offset_to_the_target() -> None:
    follower = _ready()
    cmd = follower.command(np.array([2.0, 0.9, 0.0]))
    assert cmd is not None
    assert np.allclose(cmd.look_at, [2.0, 0.9, 0.0])
    assert np.allclose(cmd.position, np.array([2.0, 0.9, 0.0]) + OFFSET)


def test_echo_of_our_own_moves_is_not_a_takeover() -> None:
    follower = _ready()
    targets = [np.array([0.04 * k, 0.9, 0.0]) for k in range(10)]
    for t in targets:
        follower.command(t)
    # Reports arrive late: they echo older commands.
    assert follower.report(targets[3] + OFFSET, targets[3]) is False
    assert follower.following


def test_orbit_and_zoom_keep_following_with_the_new_offset() -> None:
    follower = _ready()
    target = np.array([1.0, 0.9, 0.0])
    follower.command(target)
    orbit = np.array([-2.0, 1.0, -1.0])
    assert follower.report(target + orbit, target) is False
    assert follower.following
    cmd = follower.command(np.array([1.5, 0.9, 0.0]))
    assert cmd is not None
    assert np.allclose(cmd.position - cmd.look_at, orbit)


def test_panning_away_is_a_takeover_until_resumed() -> None:
    follower = _ready()
    target = np.array([1.0, 0.9, 0.0])
    follower.command(target)
    panned = target + np.array([0.0, 0.0, 0.5])
    assert follower.report(panned + OFFSET, panned) is True
    assert not follower.following
    assert follower.command(target) is None
    follower.resume()
    assert follower.command(target) is not None
