"""Measures a bundle: where each tag sits relative to a master tag, from
photos in which the master and other tags are seen together, written as a
bundle YAML that `chromatag detect --board` and chromatag.Board.from_file read.

    chromatag detect photos/ --camera camera.yaml --tag-size 40mm --json > poses.jsonl
    python3 scripts/measure_bundle.py poses.jsonl --tag-size 0.04 --master 0 -o robot.yaml
    python3 scripts/measure_bundle.py poses.jsonl --tag-size 0.04 --master 0 --size 3=0.08 \
        --name robot -o robot.yaml

Every frame that holds the master and another tag gives that tag's pose in the
master's frame (master_from_tag = camera_from_master^-1 camera_from_tag); the
estimates of each tag are averaged (the median position, the mean rotation
projected back onto a rotation). Tags whose pose is ambiguous in a frame (a
small or face-on tag, `ambiguity` above --max-ambiguity) are skipped there.
`detect --tag-size` takes one size: give the others with --size ID=METRES, and
their positions are scaled to them (a pinhole camera sees a tag twice the
size twice as far away at the same place in the image).

The bundle frame is the master tag's frame: origin at its centre, x right, y
up, z out of it. Photograph the bundle from several sides, with every tag seen
together with the master in at least a few photos (docs/pose.md).
"""
import argparse
import json
import os
import sys

import numpy as np


def rotation_from_rvec(rvec):
    rvec = np.asarray(rvec, float)
    angle = np.linalg.norm(rvec)
    if angle < 1e-12:
        return np.eye(3)
    k = rvec / angle
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def mean_rotation(rotations):
    u, _, vt = np.linalg.svd(np.sum(rotations, axis=0))
    r = u @ vt
    if np.linalg.det(r) < 0:
        r = u @ np.diag([1, 1, -1]) @ vt
    return r


def quaternion(r):
    # w, x, y, z of a rotation matrix (Shepperd: from the largest of the four
    # squared components, so that half turns come out right), w >= 0.
    squares = [1 + r[0, 0] + r[1, 1] + r[2, 2], 1 + r[0, 0] - r[1, 1] - r[2, 2],
               1 - r[0, 0] + r[1, 1] - r[2, 2], 1 - r[0, 0] - r[1, 1] + r[2, 2]]
    i = int(np.argmax(squares))
    big = np.sqrt(squares[i]) / 2
    s = 0.25 / big
    if i == 0:
        q = [big, (r[2, 1] - r[1, 2]) * s, (r[0, 2] - r[2, 0]) * s, (r[1, 0] - r[0, 1]) * s]
    elif i == 1:
        q = [(r[2, 1] - r[1, 2]) * s, big, (r[0, 1] + r[1, 0]) * s, (r[0, 2] + r[2, 0]) * s]
    elif i == 2:
        q = [(r[0, 2] - r[2, 0]) * s, (r[0, 1] + r[1, 0]) * s, big, (r[1, 2] + r[2, 1]) * s]
    else:
        q = [(r[1, 0] - r[0, 1]) * s, (r[0, 2] + r[2, 0]) * s, (r[1, 2] + r[2, 1]) * s, big]
    q = np.array(q) / np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def measure(lines, master, family, sizes, detected_size, max_ambiguity):
    """{tag id: (rotation, position, frames)} in the master's frame."""
    seen = {}
    for line in lines:
        frame = json.loads(line)
        poses = {}
        for d in frame.get("detections", []):
            if d["family"] != family or "pose" not in d:
                continue
            if d["pose"]["ambiguity"] > max_ambiguity:
                continue
            scale = sizes.get(d["id"], detected_size) / detected_size
            poses[d["id"]] = (rotation_from_rvec(d["pose"]["rvec"]),
                              scale * np.asarray(d["pose"]["tvec"], float))
        if master not in poses:
            continue
        r_m, t_m = poses[master]
        for tag, (r, t) in poses.items():
            if tag != master:
                seen.setdefault(tag, []).append((r_m.T @ r, r_m.T @ (t - t_m)))
    return {tag: (mean_rotation([r for r, _ in v]), np.median([t for _, t in v], axis=0), len(v))
            for tag, v in seen.items()}


def bundle_yaml(name, family, master, sizes, detected_size, measured):
    rows = [f"# Measured by scripts/measure_bundle.py: tag poses in tag {master}'s frame.",
            "tag_bundles:", f"  - name: {name}", f"    family: {family}", "    layout:",
            f"      - {{id: {master}, size: {sizes.get(master, detected_size):.6g}, "
            "x: 0, y: 0, z: 0, qw: 1, qx: 0, qy: 0, qz: 0}"]
    for tag in sorted(measured):
        r, t, frames = measured[tag]
        q = quaternion(r)
        rows.append(f"      - {{id: {tag}, size: {sizes.get(tag, detected_size):.6g}, "
                    f"x: {t[0]:.6f}, y: {t[1]:.6f}, z: {t[2]:.6f}, qw: {q[0]:.7f}, "
                    f"qx: {q[1]:.7f}, qy: {q[2]:.7f}, qz: {q[3]:.7f}}}  # {frames} frames")
    return "\n".join(rows) + "\n"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("poses", help="`chromatag detect --camera --tag-size --json` output")
    parser.add_argument("--master", type=int, required=True, help="the tag whose frame it is")
    parser.add_argument("--family", default="16h5", choices=["16h5", "36h11"])
    parser.add_argument("--tag-size", type=float, required=True,
                        help="the --tag-size given to detect, metres")
    parser.add_argument("--size", action="append", default=[], metavar="ID=METRES",
                        help="a tag whose size differs from --tag-size; repeatable")
    parser.add_argument("--max-ambiguity", type=float, default=0.5)
    parser.add_argument("--name", default="bundle")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args(argv)
    sizes = {}
    for item in args.size:
        tag, _, metres = item.partition("=")
        try:
            sizes[int(tag)] = float(metres)
        except ValueError:
            parser.error(f"--size {item}: give ID=METRES, e.g. 3=0.08")
    detected_size = args.tag_size
    try:
        with open(args.poses) as f:
            measured = measure(f, args.master, args.family, sizes, detected_size,
                               args.max_ambiguity)
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"measure_bundle: cannot read '{args.poses}': {e}")
    if not measured:
        sys.exit(f"measure_bundle: no frame holds tag {args.master} with another "
                 f"{args.family} tag with a pose (did detect get --camera and --tag-size?)")
    text = bundle_yaml(args.name, args.family, args.master, sizes, detected_size, measured)
    try:
        with open(args.output + ".tmp", "w") as f:
            f.write(text)
        os.replace(args.output + ".tmp", args.output)
    except OSError as e:
        sys.exit(f"measure_bundle: cannot write '{args.output}': {e}")
    print(f"measure_bundle: {len(measured) + 1} tags in {args.output}")


if __name__ == "__main__":
    main(sys.argv[1:])
