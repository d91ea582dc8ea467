#pragma once
// Where each unknown of a body's or an island's MNCP lives in z, and a contact's point on G and
// gap at z (on a plane, from a1 alone).

#include <array>
#include <vector>

#include <Eigen/Core>

#include "engine/mncp/body_step.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {

/// Where each unknown of the MNCP lives in z. Free (equality) unknowns come first: ν⁺ and per
/// contact (a1, a2, s, p_t, p_o, p_r); then the complementarity unknowns: per contact the hull
/// multipliers l (one per window constraint), the obstacle multipliers l_G, p_n and σ. Row i of
/// the residual is paired with unknown i.
///
/// A contact on a plane (G a fixed half-space, engine/README.md "Contacts on a plane") has no
/// a2, s and l_G: with one linear constraint l_G = 1, N is the plane's normal, s = g(a1)/|N|²
/// and a2 = a1 − s N, so the layout leaves them out (a2 = s = −1, l_g_count = 0) and the
/// cone rows pair with a1: 20 unknowns instead of 25 for a body on the ground.
struct MncpLayout {
  struct Contact {
    int a1, a2, s, p_t, p_o, p_r;  // free (a2, s: −1 on a plane)
    int l, l_count;                // hull multipliers
    int l_g, l_g_count;            // obstacle multipliers (none on a plane)
    int p_n, sigma;
    bool on_plane() const { return s < 0; }
  };
  int num_free = 0;
  int size = 0;
  std::vector<Contact> contacts;
};

MncpLayout MakeLayout(const BodyProblem& problem);

/// The contact blocks of a layout whose first `first` unknowns are ν⁺ of one or more bodies:
/// per contact k its free block (a1, a2, s, p_t, p_o, p_r) from `first` on, then the
/// complementarity blocks with counts[k] = {l_count, l_g_count}; l_g_count = 0 lays out a
/// contact on a plane (free block a1, p_t, p_o, p_r). MakeLayout is LayOutContacts(6, …) with
/// every contact in the general form; island_mncp.h's MakeIslandLayout lays out several bodies
/// with it, and contacts on a plane in the plane form.
MncpLayout LayOutContacts(int first, const std::vector<std::array<int, 2>>& counts);

/// Contact L's point on G and gap at z: z's a2 and s, or on a plane (`plane` the half-space)
/// a1's projection onto it and its signed distance g(a1)/|∇g|².
struct ContactGap {
  Eigen::Vector3d a2;  // m
  double s;            // m per unit of |N|
};
ContactGap ContactGapAt(const MncpLayout::Contact& L, const geometry::ConvexShape* plane,
                        const Eigen::VectorXd& z);

}  // namespace ecpsim::engine
