# The metaball family traced exactly by isotrace against Blender's own
# polygonization at render resolution 0.01 rendered by Cycles: white
# emitting metaballs on black, so a pixel's value is the part of it the
# surface covers, and the silhouettes must agree.
import sys
import unittest

import addon_test_support as support


def metaball_scene(engine):
    scene = support.empty_scene(96, 72)
    scene.render.engine = engine
    support.add_camera(scene, (0.0, -6.0, 1.5), (0, 0, 0.8), lens=50)
    white = support.principled("Glow", (0.0, 0.0, 0.0), specular=0.0, emission=(1.0, 1.0, 1.0))
    support.add_metaball_family(scene, white, resolution=0.01)
    support.set_world_color(scene, (0.0, 0.0, 0.0))
    if engine == "CYCLES":
        scene.cycles.samples = 64
        scene.cycles.max_bounces = 0
        scene.cycles.device = "CPU"
        scene.cycles.use_denoising = False  # Debian's Blender has no OpenImageDenoise
    else:
        scene.isotrace.samples = 64
        scene.isotrace.max_depth = 1
    return scene


class MetaballsAgainstCycles(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        support.install_addon()

    def test_silhouettes_agree(self):
        cycles = support.read_rgb(support.render_to(metaball_scene("CYCLES"), "cycles")).channel(1)
        isotrace = support.read_rgb(support.render_to(metaball_scene("ISOTRACE"), "isotrace")).channel(1)
        covered_cycles = sum(v > 0.5 for v in cycles)
        covered_isotrace = sum(v > 0.5 for v in isotrace)
        # The silhouette: pixels where either image is partly covered.
        edge = sum(0.02 < a < 0.98 or 0.02 < b < 0.98 for a, b in zip(cycles, isotrace))
        differing = sum((a > 0.5) != (b > 0.5) for a, b in zip(cycles, isotrace))
        mean_difference = sum(abs(a - b) for a, b in zip(cycles, isotrace)) / len(cycles)
        print(f"covered: Cycles {covered_cycles}, isotrace {covered_isotrace}; silhouette pixels {edge}, "
              f"differing at 1/2 coverage {differing}; mean |difference| {mean_difference:.4f}")
        self.assertGreater(covered_cycles, 500)
        # Both renderers filter over about a pixel (Blackman-Harris 1.5 px,
        # Gaussian sigma 0.5 px), so half-covered pixels may fall either
        # way; a surface that differed would differ over whole regions.
        self.assertLessEqual(differing, 0.1 * edge)
        self.assertLess(abs(covered_cycles - covered_isotrace), 0.02 * covered_cycles)

if __name__ == "__main__":
    result = unittest.main(argv=[sys.argv[0]], exit=False).result
    sys.exit(0 if result.wasSuccessful() else 1)
