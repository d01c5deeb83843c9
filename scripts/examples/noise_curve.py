"""How far vmas's skeleton lies from a clean mesh as noise grows, with denoising (auto) and without.
Usage: python3 noise_curve.py [MESH] [OUT.png] [SPHERES]   (default: a shared model, 60 spheres)"""
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import vmas

path = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/meshes/bear.off"
out, spheres = (sys.argv[2] if len(sys.argv) > 2 else "noise_curve.png",
                int(sys.argv[3]) if len(sys.argv) > 3 else 60)
mesh = vmas.read(path)
corners = mesh.points[mesh.faces]                   # (F, 3, 3): each face's corners
area = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
rng = np.random.default_rng(1)
face = rng.choice(len(area), 20000, p=area / area.sum())  # a 20 000-point scan of the surface
u, v = rng.random((2, 20000, 1))
u, v = np.where(u + v > 1, 1 - u, u), np.where(u + v > 1, 1 - v, v)
a, b, c = corners[face, 0], corners[face, 1], corners[face, 2]
clean = a + u * (b - a) + v * (c - a)
diagonal = np.linalg.norm(mesh.points.max(0) - mesh.points.min(0))
sigmas = [0.0, 0.5, 1.0, 2.0]                       # % of the diagonal
noisy = [clean + rng.normal(scale=s / 100 * diagonal, size=clean.shape) for s in sigmas]
for denoise in ("auto", "off"):
    errors = []
    for sigma, cloud in zip(sigmas, noisy):
        result = vmas.skeletonize(cloud, spheres=spheres, denoise=denoise)
        errors.append(vmas.evaluate(mesh, result)["hausdorff_percent"])
        print(f"denoise={denoise} sigma={sigma} %: epsilon {errors[-1]:.2f} % of the diagonal")
    plt.plot(sigmas, errors, "o-", label=f"denoise={denoise!r}")
plt.xlabel("noise σ (% of the diagonal)")
plt.ylabel("ε against the clean mesh (% of the diagonal)")
plt.title(f"{path.split('/')[-1]}, {spheres} spheres, 20 000 points")
plt.legend()
plt.grid(alpha=0.3)
plt.savefig(out, dpi=90)
print("wrote", out)
