// `tether import`: a tether scene from an MJCF (MuJoCo) or URDF (ROS) model. docs/import.md describes the
// mapping; this is its interface:
//
//   ImportModel(path)            reads the model by its extension (.xml: MJCF through MuJoCo's compiler, .urdf:
//                                URDF through urdfdom) into a KinematicTree, then builds the scene from it;
//   SceneFromTree(tree)          the mapping itself: links become rigid bodies (centre of mass, inertia about it in
//                                the link's axes, the link's orientation), joints become constraints, springs,
//                                dampers and motors become effects, sites become markers, and what tether cannot
//                                express becomes one warning per kind.
//
// Errors are InputErrors naming the model's file (or the flag at fault): exit status 2 in the command line.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "tether/importers/kinematic_tree.h"

namespace tether::importers {

struct ImportOptions {
  std::vector<std::pair<std::string, double>> joint_values;  // --joint NAME=VALUE: initial coordinates, rad or m
  std::vector<std::pair<std::string, double>> joint_rates;   // --joint-velocity NAME=RATE: rad/s or m/s
  std::vector<std::string> fixed_bodies;                     // --fix BODY: part of the world where it starts
  bool merge_fixed = false;   // --merge-fixed: welded links join their parent's body instead of a weld
  bool split_joints = false;  // --split-joints: every joint its own constraint, through light intermediate bodies
  bool contact = true;        // false (--no-contact): the collision shapes are drawn only ("contact": false)
};

struct ImportedScene {
  nlohmann::ordered_json scene;        // valid for ParseScene (checked before it is returned)
  std::vector<std::string> warnings;   // one sentence per kind of thing dropped or approximated
};

// `source` names the model in messages.
ImportedScene SceneFromTree(const KinematicTree& tree, const ImportOptions& options, const std::string& source);

ImportedScene ImportModel(const std::string& path, const ImportOptions& options);

// The model readers (mjcf_reader.cc or mjcf_unavailable.cc, urdf_reader.cc). Throw InputError naming `path`.
KinematicTree ReadMjcf(const std::string& path);
KinematicTree ReadUrdf(const std::string& path);

}  // namespace tether::importers
