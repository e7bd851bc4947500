"""Child process of addon/denoise.py: denoises the passes in a .npz file with purlcore.

    python denoise_worker.py in.npz out.npz        (PYTHONPATH: the folder holding purlcore)

Prints one line saying why and exits 1 when Open Image Denoise is missing or fails.
"""
import sys

import numpy as np


def main(source, target):
    try:
        import purlcore
    except ImportError as error:
        print("purlcore does not load outside Blender: {}".format(error))
        return 1
    status = purlcore.denoiser()
    if not status["available"]:
        print(" ".join(status["message"].split()))
        return 1
    with np.load(source) as data:
        passes = {name: data[name] for name in data.files}
    try:
        result = purlcore.denoise(passes)
    except RuntimeError as error:
        print(error)
        return 1
    np.savez(target, **{name: result[name] for name in ("Combined", "Noisy Image")})
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]))
