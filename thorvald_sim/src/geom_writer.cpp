#include "thorvald_sim/geom_writer.h"

#include <algorithm>
#include <cmath>

namespace thorvald_sim {

void GeomWriter::head(const std::string& name, const char* type) {
  out_ << "<geom name=\"" << name << "\" type=\"" << type << "\"";
}

void GeomWriter::vec(const char* attr, const Eigen::Vector3d& v) {
  out_ << " " << attr << "=\"" << v.x() << " " << v.y() << " " << v.z() << "\"";
}

void GeomWriter::plane(const std::string& name, const Eigen::Vector3d& pos, double half_size, const char* rgba) {
  tiltedPlane(name, pos, half_size, 0.0, rgba);
}

void GeomWriter::tiltedPlane(const std::string& name, const Eigen::Vector3d& pos, double half_size, double pitch_rad,
                             const char* rgba) {
  head(name, "plane");
  vec("pos", pos);
  // size[2] is only the grid spacing of the plane's drawing: one cell keeps camera rendering cheap.
  out_ << " size=\"" << half_size << " " << half_size << " " << half_size << "\" euler=\"0 " << pitch_rad
       << " 0\" rgba=\"" << rgba << "\"/>\n";
}

void GeomWriter::box(const std::string& name, const Eigen::Vector3d& pos, const Eigen::Vector3d& half,
                     const char* rgba) {
  head(name, "box");
  vec("pos", pos);
  vec("size", half);
  out_ << " rgba=\"" << rgba << "\"/>\n";
}

void GeomWriter::capsule(const std::string& name, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius,
                         const char* rgba) {
  head(name, "capsule");
  out_ << " fromto=\"" << from.x() << " " << from.y() << " " << from.z() << " " << to.x() << " " << to.y() << " "
       << to.z() << "\" size=\"" << radius << "\" rgba=\"" << rgba << "\"/>\n";
}

void GeomWriter::cylinderBetween(const std::string& name, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                 double radius, const char* rgba) {
  head(name, "cylinder");
  out_ << " fromto=\"" << from.x() << " " << from.y() << " " << from.z() << " " << to.x() << " " << to.y() << " "
       << to.z() << "\" size=\"" << radius << "\" rgba=\"" << rgba << "\"/>\n";
}

void GeomWriter::cylinder(const std::string& name, const Eigen::Vector3d& pos, double radius, double half_height,
                          const char* rgba) {
  head(name, "cylinder");
  vec("pos", pos);
  out_ << " size=\"" << radius << " " << half_height << "\" rgba=\"" << rgba << "\"/>\n";
}

void GeomWriter::sphere(const std::string& name, const Eigen::Vector3d& pos, double radius, const char* rgba) {
  head(name, "sphere");
  vec("pos", pos);
  out_ << " size=\"" << radius << "\" rgba=\"" << rgba << "\"/>\n";
}

void GeomWriter::ellipsoid(const std::string& name, const Eigen::Vector3d& pos, const Eigen::Vector3d& half,
                           double yaw_rad, const char* rgba) {
  head(name, "ellipsoid");
  vec("pos", pos);
  vec("size", half);
  out_ << " euler=\"0 0 " << yaw_rad << "\" rgba=\"" << rgba << "\"/>\n";
}

void GeomWriter::capsulePieces(const std::string& name, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                               double radius, const char* rgba, double piece_m) {
  const int n = std::max(1, static_cast<int>(std::ceil((to - from).norm() / piece_m)));
  for (int k = 0; k < n; ++k)
    capsule(name + "_s" + std::to_string(k), from + (to - from) * (double(k) / n),
            from + (to - from) * (double(k + 1) / n), radius, rgba);
}

void GeomWriter::boxPieces(const std::string& name, const Eigen::Vector3d& pos, const Eigen::Vector3d& half,
                           const char* rgba, double piece_m) {
  const int nx = std::max(1, static_cast<int>(std::ceil(2 * half.x() / piece_m)));
  const int ny = std::max(1, static_cast<int>(std::ceil(2 * half.y() / piece_m)));
  const Eigen::Vector3d piece(half.x() / nx, half.y() / ny, half.z());
  int k = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j, ++k)
      box(name + "_s" + std::to_string(k),
          pos + Eigen::Vector3d(-half.x() + (2 * i + 1) * piece.x(), -half.y() + (2 * j + 1) * piece.y(), 0.0), piece,
          rgba);
}

}  // namespace thorvald_sim
