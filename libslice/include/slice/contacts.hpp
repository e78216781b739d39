#pragma once
// The contacts of a block model (docs/dem-exports.md, "Contacts"): where two kept blocks touch
// face to face across a joint. The DEM exports give each contact its joint's strength from them
// (3DEC by joint-set ID, YADE per contact). Needs /geometry.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "slice/h5io.hpp"

namespace slice {

/// Two kept blocks touching across one joint: a face of each on the joint, facing each other,
/// overlapping with positive area (more than the scene's tolerance across every direction).
struct BlockContact {
  std::size_t a = 0, b = 0;            // block rows, a < b (a kept one first beside a removed one)
  std::size_t face_a = 0, face_b = 0;  // their faces' rows in the per-face arrays
  std::int64_t joint = -1;
  double area = 0;               // of the overlap of the two faces, clipped exactly
  Vec3 centroid = Vec3::Zero();  // of the overlap
  Vec3 normal = Vec3::UnitZ();   // unit: block a's outward normal (from a towards b)
  /// An upper bound on the part of the contact that lies on its joint's polygon: the part of
  /// either face on it, min(f_a A_a, f_b A_b) (f: /geometry/face_joint_fraction, A: face area).
  double open = 0;
};

/// Which faces the contact search looks at: construction joints too; removed blocks too (a
/// contact of a kept block with a removed one: where the kept block is free; two removed blocks
/// have none).
struct ContactScope {
  bool construction = false;
  bool removed = false;
  bool polygons = false;  // hand the visitor each overlap polygon (else an empty span)
};

/// Called with each contact and, if the scope asks for them, the polygon of its overlap (global
/// frame, counter-clockwise about `normal`), joint by joint, in an order that depends on the
/// blocks only.
using ContactVisitor = std::function<void(const BlockContact&, std::span<const Vec3> polygon)>;
void for_each_contact(const BlockSystem& bs, ContactScope scope, const ContactVisitor& visit);

/// Every contact across rock and boundary joints (and construction joints too with
/// `construction`), sorted by (a, b, joint, face_a, face_b). Removed blocks have none. Throws
/// Error without /geometry.
std::vector<BlockContact> find_contacts(const BlockSystem& bs, bool construction = false);

/// The rock-bridge rule of the exports (docs/3dec.md, "Rock bridges"): with a [rock] table, a
/// contact at most half of which lies on its joint's polygon is intact rock.
inline bool is_rock_bridge(const BlockSystem& bs, const BlockContact& c) {
  return bs.joints.rock.given && c.open < 0.5 * c.area;
}

}  // namespace slice
