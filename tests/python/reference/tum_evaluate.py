#!/usr/bin/python3
# Software License Agreement (BSD License)
#
# Copyright (c) 2013, Juergen Sturm, TUM
# All rights reserved.
#
# Redistribution and use in source and binary forms, with or without
# modification, are permitted provided that the following conditions
# are met:
#
#  * Redistributions of source code must retain the above copyright
#    notice, this list of conditions and the following disclaimer.
#  * Redistributions in binary form must reproduce the above
#    copyright notice, this list of conditions and the following
#    disclaimer in the documentation and/or other materials provided
#    with the distribution.
#  * Neither the name of TUM nor the names of its
#    contributors may be used to endorse or promote products derived
#    from this software without specific prior written permission.
#
# THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS
# "AS IS" AND ANY EXPRESS OR IMPLIED WARRANTIES, INCLUDING, BUT NOT
# LIMITED TO, THE IMPLIED WARRANTIES OF MERCHANTABILITY AND FITNESS
# FOR A PARTICULAR PURPOSE ARE DISCLAIMED. IN NO EVENT SHALL THE
# COPYRIGHT OWNER OR CONTRIBUTORS BE LIABLE FOR ANY DIRECT, INDIRECT,
# INCIDENTAL, SPECIAL, EXEMPLARY, OR CONSEQUENTIAL DAMAGES (INCLUDING,
# BUT NOT LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR SERVICES;
# LOSS OF USE, DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER
# CAUSED AND ON ANY THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT
# LIABILITY, OR TORT (INCLUDING NEGLIGENCE OR OTHERWISE) ARISING IN
# ANY WAY OUT OF THE USE OF THIS SOFTWARE, EVEN IF ADVISED OF THE
# POSSIBILITY OF SUCH DAMAGE.
"""
Reference evaluator for lrd-slam's tests: a Python 3 port of the TUM RGB-D benchmark tools
associate.py, evaluate_ate.py and evaluate_rpe.py (Juergen Sturm, TUM, BSD licence above),
following the original functions line by line. Changes from the originals, all mechanical:

  * Python 2 -> 3: print(), list(d.keys()) where the scripts sort or remove from keys().
  * numpy.matrix -> ndarray with explicit '@' and (3,1) column means (same arithmetic).
  * transform44(): the near-zero-quaternion branch of the original lacks the commas between the
    rows (it would raise TypeError); here it returns the identity rotation it evidently intends.
  * evaluate_rpe's random sampling is disabled by max_pairs=0, which the original script supports
    ("set to zero to disable downsampling"): lrd-slam evaluates ALL pairs.
  * evaluate(): evaluate_ate.py reads files with associate.read_file_list(), which keeps entries
    with NaNs or an all-zero quaternion; lrd-slam reads both files once, the evaluate_rpe.py way,
    which drops them. evaluate(..., ate_skip_invalid=True) (the default) applies that same filter
    before the ATE, so the two agree on such files too. Files without such entries are unaffected.

Usage: tum_evaluate.py GT EST [--max_difference 0.02] [--delta 1.0]  -> JSON like `lrdslam eval --json`.
"""

import argparse
import json
import sys

import numpy

# ---------------------------------------------------------------------------------------------
# associate.py
# ---------------------------------------------------------------------------------------------


def read_file_list(filename):
    """
    Reads a trajectory from a text file.

    File format:
    The file format is "stamp d1 d2 d3 ...", where stamp denotes the time stamp (to be matched)
    and "d1 d2 d3.." is arbitary data (e.g., a 3D position and 3D orientation) associated to this timestamp.

    Input:
    filename -- File name

    Output:
    dict -- dictionary of (stamp,data) tuples
    """
    file = open(filename)
    data = file.read()
    file.close()
    lines = data.replace(",", " ").replace("\t", " ").split("\n")
    list = [[v.strip() for v in line.split(" ") if v.strip() != ""] for line in lines if len(line) > 0 and line[0] != "#"]
    list = [(float(l[0]), l[1:]) for l in list if len(l) > 1]
    return dict(list)


def associate(first_list, second_list, offset, max_difference):
    """
    Associate two dictionaries of (stamp,data). As the time stamps never match exactly, we aim
    to find the closest match for every input tuple.

    Input:
    first_list -- first dictionary of (stamp,data) tuples
    second_list -- second dictionary of (stamp,data) tuples
    offset -- time offset between both dictionaries (e.g., to model the delay between the sensors)
    max_difference -- search radius for candidate generation

    Output:
    matches -- list of matched tuples ((stamp1,data1),(stamp2,data2))
    """
    first_keys = list(first_list.keys())
    second_keys = list(second_list.keys())
    potential_matches = [(abs(a - (b + offset)), a, b)
                         for a in first_keys
                         for b in second_keys
                         if abs(a - (b + offset)) < max_difference]
    potential_matches.sort()
    matches = []
    for diff, a, b in potential_matches:
        if a in first_keys and b in second_keys:
            first_keys.remove(a)
            second_keys.remove(b)
            matches.append((a, b))

    matches.sort()
    return matches


# ---------------------------------------------------------------------------------------------
# evaluate_ate.py
# ---------------------------------------------------------------------------------------------


def align(model, data):
    """Align two trajectories using the method of Horn (closed-form).

    Input:
    model -- first trajectory (3xn)
    data -- second trajectory (3xn)

    Output:
    rot -- rotation matrix (3x3)
    trans -- translation vector (3x1)
    trans_error -- translational error per point (1xn)
    """
    model_zerocentered = model - model.mean(1).reshape(3, 1)
    data_zerocentered = data - data.mean(1).reshape(3, 1)

    W = numpy.zeros((3, 3))
    for column in range(model.shape[1]):
        W += numpy.outer(model_zerocentered[:, column], data_zerocentered[:, column])
    U, d, Vh = numpy.linalg.svd(W.transpose())
    S = numpy.identity(3)
    if numpy.linalg.det(U) * numpy.linalg.det(Vh) < 0:
        S[2, 2] = -1
    rot = U @ S @ Vh
    trans = data.mean(1).reshape(3, 1) - rot @ model.mean(1).reshape(3, 1)

    model_aligned = rot @ model + trans
    alignment_error = model_aligned - data

    trans_error = numpy.sqrt(numpy.sum(numpy.multiply(alignment_error, alignment_error), 0))

    return rot, trans, trans_error


def evaluate_ate(first_list, second_list, offset=0.0, scale=1.0, max_difference=0.02):
    """The body of evaluate_ate.py's __main__ up to the printed statistics."""
    matches = associate(first_list, second_list, float(offset), float(max_difference))
    if len(matches) < 2:
        raise Exception("Couldn't find matching timestamp pairs between groundtruth and estimated trajectory! "
                        "Did you choose the correct sequence?")

    first_xyz = numpy.array([[float(value) for value in first_list[a][0:3]] for a, b in matches]).transpose()
    second_xyz = numpy.array([[float(value) * float(scale) for value in second_list[b][0:3]]
                              for a, b in matches]).transpose()
    rot, trans, trans_error = align(second_xyz, first_xyz)
    return matches, rot, trans, trans_error


# ---------------------------------------------------------------------------------------------
# evaluate_rpe.py
# ---------------------------------------------------------------------------------------------

_EPS = numpy.finfo(float).eps * 4.0


def transform44(l):
    """
    Generate a 4x4 homogeneous transformation matrix from a 3D point and unit quaternion.

    Input:
    l -- tuple consisting of (stamp,tx,ty,tz,qx,qy,qz,qw) where
         (tx,ty,tz) is the 3D position and (qx,qy,qz,qw) is the unit quaternion.

    Output:
    matrix -- 4x4 homogeneous transformation matrix
    """
    t = l[1:4]
    q = numpy.array(l[4:8], dtype=numpy.float64, copy=True)
    nq = numpy.dot(q, q)
    if nq < _EPS:
        return numpy.array((
            (1.0, 0.0, 0.0, t[0]),
            (0.0, 1.0, 0.0, t[1]),
            (0.0, 0.0, 1.0, t[2]),
            (0.0, 0.0, 0.0, 1.0)), dtype=numpy.float64)
    q *= numpy.sqrt(2.0 / nq)
    q = numpy.outer(q, q)
    return numpy.array((
        (1.0 - q[1, 1] - q[2, 2], q[0, 1] - q[2, 3], q[0, 2] + q[1, 3], t[0]),
        (q[0, 1] + q[2, 3], 1.0 - q[0, 0] - q[2, 2], q[1, 2] - q[0, 3], t[1]),
        (q[0, 2] - q[1, 3], q[1, 2] + q[0, 3], 1.0 - q[0, 0] - q[1, 1], t[2]),
        (0.0, 0.0, 0.0, 1.0)), dtype=numpy.float64)


def read_trajectory(filename, matrix=True):
    """
    Read a trajectory from a text file.

    Input:
    filename -- file to be read
    matrix -- convert poses to 4x4 matrices

    Output:
    dictionary of stamped 3D poses
    """
    file = open(filename)
    data = file.read()
    file.close()
    lines = data.replace(",", " ").replace("\t", " ").split("\n")
    list = [[float(v.strip()) for v in line.split(" ") if v.strip() != ""] for line in lines if len(line) > 0 and line[0] != "#"]
    list_ok = []
    for i, l in enumerate(list):
        if l[4:8] == [0, 0, 0, 0]:
            continue
        isnan = False
        for v in l:
            if numpy.isnan(v):
                isnan = True
                break
        if isnan:
            sys.stderr.write("Warning: line %d of file '%s' has NaNs, skipping line\n" % (i, filename))
            continue
        list_ok.append(l)
    if matrix:
        traj = dict([(l[0], transform44(l[0:])) for l in list_ok])
    else:
        traj = dict([(l[0], l[1:8]) for l in list_ok])
    return traj


def find_closest_index(L, t):
    """
    Find the index of the closest value in a list.

    Input:
    L -- the list
    t -- value to be found

    Output:
    index of the closest element
    """
    beginning = 0
    difference = abs(L[0] - t)
    best = 0
    end = len(L)
    while beginning < end:
        middle = int((end + beginning) / 2)
        if abs(L[middle] - t) < difference:
            difference = abs(L[middle] - t)
            best = middle
        if t == L[middle]:
            return middle
        elif L[middle] > t:
            end = middle
        else:
            beginning = middle + 1
    return best


def ominus(a, b):
    """
    Compute the relative 3D transformation between a and b.

    Input:
    a -- first pose (homogeneous 4x4 matrix)
    b -- second pose (homogeneous 4x4 matrix)

    Output:
    Relative 3D transformation from a to b.
    """
    return numpy.dot(numpy.linalg.inv(a), b)


def scale(a, scalar):
    """
    Scale the translational components of a 4x4 homogeneous matrix by a scale factor.
    """
    return numpy.array(
        [[a[0, 0], a[0, 1], a[0, 2], a[0, 3] * scalar],
         [a[1, 0], a[1, 1], a[1, 2], a[1, 3] * scalar],
         [a[2, 0], a[2, 1], a[2, 2], a[2, 3] * scalar],
         [a[3, 0], a[3, 1], a[3, 2], a[3, 3]]])


def compute_distance(transform):
    """
    Compute the distance of the translational component of a 4x4 homogeneous matrix.
    """
    return numpy.linalg.norm(transform[0:3, 3])


def compute_angle(transform):
    """
    Compute the rotation angle from a 4x4 homogeneous matrix.
    """
    # an invitation to 3-d vision, p 27
    return numpy.arccos(min(1, max(-1, (numpy.trace(transform[0:3, 0:3]) - 1) / 2)))


def evaluate_trajectory(traj_gt, traj_est, param_max_pairs=10000, param_fixed_delta=False, param_delta=1.00,
                        param_delta_unit="s", param_offset=0.00, param_scale=1.00):
    """
    Compute the relative pose error between two trajectories (only the branches lrd-slam uses:
    param_delta_unit "s"; param_fixed_delta True; param_max_pairs 0 keeps all pairs).

    Output:
    list of compared poses and the resulting translation and rotation error
    """
    stamps_gt = list(traj_gt.keys())
    stamps_est = list(traj_est.keys())
    stamps_gt.sort()
    stamps_est.sort()

    stamps_est_return = []
    for t_est in stamps_est:
        t_gt = stamps_gt[find_closest_index(stamps_gt, t_est + param_offset)]
        t_est_return = stamps_est[find_closest_index(stamps_est, t_gt - param_offset)]
        t_gt_return = stamps_gt[find_closest_index(stamps_gt, t_est_return + param_offset)]  # noqa: F841
        if t_est_return not in stamps_est_return:
            stamps_est_return.append(t_est_return)
    if len(stamps_est_return) < 2:
        raise Exception("Number of overlap in the timestamps is too small. Did you run the evaluation on the right files?")

    if param_delta_unit == "s":
        index_est = list(traj_est.keys())
        index_est.sort()
    else:
        raise Exception("Unknown unit for delta: '%s'" % param_delta_unit)

    if not param_fixed_delta:
        raise Exception("only --fixed_delta is ported")
    else:
        pairs = []
        for i in range(len(traj_est)):
            j = find_closest_index(index_est, index_est[i] + param_delta)
            if j != len(traj_est) - 1:
                pairs.append((i, j))
        if param_max_pairs != 0 and len(pairs) > param_max_pairs:
            raise Exception("random subsampling is not ported; pass param_max_pairs=0")

    gt_interval = numpy.median([s - t for s, t in zip(stamps_gt[1:], stamps_gt[:-1])])
    gt_max_time_difference = 2 * gt_interval

    result = []
    for i, j in pairs:
        stamp_est_0 = stamps_est[i]
        stamp_est_1 = stamps_est[j]

        stamp_gt_0 = stamps_gt[find_closest_index(stamps_gt, stamp_est_0 + param_offset)]
        stamp_gt_1 = stamps_gt[find_closest_index(stamps_gt, stamp_est_1 + param_offset)]

        if (abs(stamp_gt_0 - (stamp_est_0 + param_offset)) > gt_max_time_difference or
                abs(stamp_gt_1 - (stamp_est_1 + param_offset)) > gt_max_time_difference):
            continue

        error44 = ominus(scale(ominus(traj_est[stamp_est_1], traj_est[stamp_est_0]), param_scale),
                         ominus(traj_gt[stamp_gt_1], traj_gt[stamp_gt_0]))

        trans = compute_distance(error44)
        rot = compute_angle(error44)

        result.append([stamp_est_0, stamp_est_1, stamp_gt_0, stamp_gt_1, trans, rot])

    if len(result) < 2:
        raise Exception("Couldn't find matching timestamp pairs between groundtruth and estimated trajectory!")

    return result


# ---------------------------------------------------------------------------------------------
# The statistics both scripts print with --verbose, in lrd-slam's JSON schema.
# ---------------------------------------------------------------------------------------------


def statistics(errors, factor=1.0):
    errors = numpy.asarray(errors, dtype=numpy.float64)
    return {
        "rmse": float(numpy.sqrt(numpy.dot(errors, errors) / len(errors)) * factor),
        "mean": float(numpy.mean(errors) * factor),
        "median": float(numpy.median(errors) * factor),
        "std": float(numpy.std(errors) * factor),
        "min": float(numpy.min(errors) * factor),
        "max": float(numpy.max(errors) * factor),
        "pairs": int(len(errors)),
    }


def _is_valid_rpe_entry(stamp, data):
    values = [stamp] + [float(v) for v in data]
    return values[4:8] != [0, 0, 0, 0] and not any(numpy.isnan(v) for v in values)


def evaluate(gt_file, est_file, max_difference=0.02, delta=1.0, ate_skip_invalid=True):
    """ATE (evaluate_ate.py) and RPE (evaluate_rpe.py --fixed_delta --delta_unit s --max_pairs 0)."""
    first_list = read_file_list(gt_file)
    second_list = read_file_list(est_file)
    if ate_skip_invalid:
        first_list = {k: v for k, v in first_list.items() if _is_valid_rpe_entry(k, v)}
        second_list = {k: v for k, v in second_list.items() if _is_valid_rpe_entry(k, v)}
    matches, rot, trans, trans_error = evaluate_ate(first_list, second_list, 0.0, 1.0, max_difference)

    traj_gt = read_trajectory(gt_file)
    traj_est = read_trajectory(est_file)
    result = evaluate_trajectory(traj_gt, traj_est, 0, True, float(delta), "s", 0.0, 1.0)
    rpe_trans = numpy.array(result)[:, 4]
    rpe_rot = numpy.array(result)[:, 5]
    return {
        "ate": statistics(trans_error),
        "rpe_trans": statistics(rpe_trans),
        "rpe_rot": statistics(rpe_rot, 180.0 / numpy.pi),
    }


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="TUM ATE/RPE reference (see module docstring)")
    parser.add_argument("groundtruth_file")
    parser.add_argument("estimated_file")
    parser.add_argument("--max_difference", type=float, default=0.02)
    parser.add_argument("--delta", type=float, default=1.0)
    args = parser.parse_args()
    print(json.dumps(evaluate(args.groundtruth_file, args.estimated_file, args.max_difference, args.delta), indent=2))
