#include "geometry/posed_shape.h"

#include <utility>
#include <vector>

namespace ecpsim::geometry {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

class PosedShape final : public ConvexShape {
 public:
  PosedShape(std::shared_ptr<const ConvexShape> shape, const Matrix3d& R, const Vector3d& p)
      : shape_(std::move(shape)), R_(R), p_(p) {}

  int NumConstraints() const override { return shape_->NumConstraints(); }
  double Value(int i, const Vector3d& y) const override { return shape_->Value(i, Local(y)); }
  Vector3d Gradient(int i, const Vector3d& y) const override {
    return R_ * shape_->Gradient(i, Local(y));
  }
  Matrix3d Hessian(int i, const Vector3d& y) const override {
    return R_ * shape_->Hessian(i, Local(y)) * R_.transpose();
  }
  bool IsLinear(int i) const override { return shape_->IsLinear(i); }
  Vector3d Support(const Vector3d& direction) const override {
    return R_ * shape_->Support(R_.transpose() * direction) + p_;
  }
  std::vector<int> ConstraintsNearSupport(const Vector3d& direction, int rings) const override {
    return shape_->ConstraintsNearSupport(R_.transpose() * direction, rings);
  }
  TriangleMesh Tessellate(int segments) const override {
    TriangleMesh mesh = shape_->Tessellate(segments);
    for (Vector3d& v : mesh.vertices) v = R_ * v + p_;
    return mesh;
  }

 private:
  Vector3d Local(const Vector3d& y) const { return R_.transpose() * (y - p_); }

  std::shared_ptr<const ConvexShape> shape_;
  Matrix3d R_;
  Vector3d p_;
};

}  // namespace

std::shared_ptr<const ConvexShape> Posed(std::shared_ptr<const ConvexShape> shape,
                                         const Matrix3d& R, const Vector3d& p) {
  if (R == Matrix3d::Identity() && p == Vector3d::Zero()) return shape;
  if (const PolyhedralShape* polyhedron = shape->AsPolyhedron()) {
    ConvexHull hull = polyhedron->hull();
    for (Vector3d& v : hull.vertices) v = R * v + p;
    for (size_t i = 0; i < hull.normals.size(); ++i) {
      hull.normals[i] = R * hull.normals[i];
      hull.offsets[i] += hull.normals[i].dot(p);
    }
    return std::make_shared<PolyhedralShape>(std::move(hull));
  }
  return std::make_shared<PosedShape>(std::move(shape), R, p);
}

}  // namespace ecpsim::geometry
