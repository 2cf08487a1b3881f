"""The 3-D damage picture tells brick cracking from joint cracking: the
units' crack interfaces are drawn in the units' reds, the mortar joints in
blues, and nothing undamaged is coloured."""
import numpy as np
import pytest

from masonrydem.dem import kernels as K
from masonrydem.scene import build_scene
from masonrydem.dem import Numerics, init
from masonrydem.specimen.build import build

# the quasi-static integration these tests were written at (local damping 0.8)
QS = Numerics(damping=0.8, safety=0.9)

from masonrydem.report.pictures import picture_damage
from masonrydem.specimen.state import state_blocks

WILLIS = "config/scenes/willis.yaml"


@pytest.fixture(scope="module")
def specimen():
    return build(build_scene(WILLIS))


def _picture(specimen, damaged, tmp_path):
    """The picture's pixels (bars and title cut off) with D = 1 on the
    sub-contacts of the joints for which ``damaged(kind)`` is true."""
    state = init(specimen.assembly, QS)
    for c, jn in zip(specimen.assembly.contacts, specimen.contact_joint):
        if damaged(specimen.joints[jn][0]):
            state.joints.state[c.sc, K.JS_D] = 1.0
    path = tmp_path / "damage.png"
    picture_damage(state_blocks(specimen, state), path, magnify=1.0, window=(800, 500))
    import matplotlib.image
    img = (matplotlib.image.imread(path)[:, :, :3] * 255).astype(int)
    return img[40:-80]          # the title above, the colour bars below


def _hues(img):
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    red = (r > 2 * g + 20) & (r > 2 * b + 20) & (r > 60)
    blue = (b > 2 * r + 20) & (b > g + 20)
    return int(red.sum()), int(blue.sum())


def test_cracked_units_show_red_and_no_blue(specimen, tmp_path):
    red, blue = _hues(_picture(specimen, lambda kind: kind == "crack", tmp_path))
    assert red > 500 and blue == 0


def test_cracked_mortar_joints_show_blue_and_no_red(specimen, tmp_path):
    red, blue = _hues(_picture(specimen, lambda kind: kind != "crack", tmp_path))
    assert blue > 500 and red == 0


def test_an_undamaged_wall_shows_neither(specimen, tmp_path):
    assert _hues(_picture(specimen, lambda kind: False, tmp_path)) == (0, 0)


def test_the_state_says_which_sub_contacts_are_crack_interfaces(specimen):
    state = init(specimen.assembly, QS)
    joints = state_blocks(specimen, state)["joints"]
    kinds = np.array([kind for kind, _ in specimen.joints])
    assert np.array_equal(joints.point_data["crack"] == 1, kinds[joints.point_data["joint"] - 1] == "crack")
    assert set(np.unique(joints.point_data["axis"])) <= {0, 2}     # a single wythe: head and bed planes
