#pragma once
// Scenes built in code: boxes and meshes as bodies on a ground plane (tests, benchmarks).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/scene.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::engine {

/// A solid box body (size in m, mass in kg) with closed-form inertia; its mesh is the hull's
/// triangulation; at rest at the origin.
Body MakeBoxBody(const Eigen::Vector3d& size, double mass, const std::string& name = "box");

/// A body from a closed mesh (any frame): moved into its CM frame, hull from CGAL, given mass.
/// @throws InputError (naming `name`) for a mesh without volume.
Body MakeMeshBody(const geometry::TriangleMesh& mesh_any_frame, double mass,
                  const std::string& name);

/// A scene with the ground, the half-space `up` · x ≤ 0 (`up` unit, world; by default z ≤ 0), and
/// the given bodies, each dynamic one in contact with the ground with `friction`; source "code",
/// step h, duration 1 s. It passes ValidateScene and is indexed (IndexContacts): a caller that
/// edits it afterwards (bodies, pairs, loads, h) builds a scene of its own, to check again (and
/// to index again where it adds pairs).
/// @throws SceneError (scene_io/scene_validation.h) naming the Scene's key, e.g.
///         `bodies[0].mass = -1: expected ...` or `h = 0: expected ...`, for a scene it rejects.
Scene MakeGroundScene(std::vector<Body> bodies, double h, const Friction& friction,
                      const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

/// Adds AddBodyContacts(i, j, PairFriction of the two bodies) for every pair i < j of `scene`'s
/// bodies that are not both kinematic, and indexes the contacts again (IndexContacts).
void AddBodyPairs(Scene& scene);

}  // namespace ecpsim::engine
