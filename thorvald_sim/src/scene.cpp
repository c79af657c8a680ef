#include "thorvald_sim/scene.h"

#include <tinyxml2.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

#include "thorvald_sim/mjcf_compiler.h"

namespace thorvald_sim {

namespace {

std::string stripPrefix(const std::string& name) {
  const auto slash = name.rfind('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

std::string num(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

bool isWheelBody(const std::string& body) {
  static const std::regex re("(wheel_link[0-9]+|caster[0-9]+_wheel.*|passive_wheel[0-9]+.*)");
  return std::regex_match(stripPrefix(body), re);
}

struct Actuator {
  std::string joint;
  bool position;
  double wheel_radius_m = 0.0;  ///< wheels: radius of the wheel's contact geom
};

// Radius of the first sphere or cylinder geom of a wheel body, 0 if none.
double wheelRadius(tinyxml2::XMLElement* body) {
  for (auto* g = body->FirstChildElement("geom"); g; g = g->NextSiblingElement("geom")) {
    const char* type = g->Attribute("type");
    if (!type || (std::string(type) != "sphere" && std::string(type) != "cylinder")) continue;
    std::istringstream size(g->Attribute("size") ? g->Attribute("size") : "");
    double r = 0;
    size >> r;
    if (r > 0) return r;
  }
  return 0.0;
}

// Sum of the masses of a body and everything below it [kg].
double treeMass(tinyxml2::XMLElement* body) {
  double m = 0.0;
  if (auto* in = body->FirstChildElement("inertial")) m += in->DoubleAttribute("mass", 0.0);
  for (auto* c = body->FirstChildElement("body"); c; c = c->NextSiblingElement("body")) m += treeMass(c);
  return m;
}

// Tunes one robot's bodies in place and collects its actuated joints.
/// Collision bits of one robot's geoms: bit 1 (type 2) meets the world (conaffinity 3), bit 0 (affinity 1) takes the
/// world's and actors' type 1; robot i also has type bit 2 + i and the affinity bits of every other robot, so robots
/// collide with each other but not with themselves. Robots past the 29th get no bit of their own (no robot contact).
struct CollisionBits {
  int contype = 2, conaffinity = 1;
};

CollisionBits robotBits(size_t index, size_t robots) {
  constexpr size_t kMaxBits = 29;
  CollisionBits b;
  for (size_t j = 0; j < std::min(robots, kMaxBits); ++j) {
    if (j == index)
      b.contype |= 4 << j;
    else
      b.conaffinity |= 4 << j;
  }
  return b;
}

void tuneBody(tinyxml2::XMLElement* body, const SceneOptions& o, const CollisionBits& bits,
              std::vector<Actuator>* actuators) {
  const char* bname = body->Attribute("name");
  const bool wheel = bname && isWheelBody(bname);
  for (auto* j = body->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* n = j->Attribute("name");
    if (!n || (j->Attribute("type") && std::string(j->Attribute("type")) == "free")) continue;
    switch (jointRole(stripPrefix(n))) {
      case JointRole::kSteering:
        j->SetAttribute("armature", num(o.steering_armature).c_str());
        j->SetAttribute("damping", num(o.steering_damping).c_str());
        actuators->push_back({n, true});
        break;
      case JointRole::kWheel:
        // A velocity servo kv (target - qvel) split in two: joint damping kv (integrated implicitly, so stiff
        // gains stay stable with the cheap Euler integrator) and a motor pushing kv * target.
        j->SetAttribute("armature", num(o.wheel_armature).c_str());
        j->SetAttribute("damping", num(o.wheel_kv).c_str());
        actuators->push_back({n, false});
        break;
      case JointRole::kPassive:
        j->SetAttribute("armature", "0.01");
        j->SetAttribute("damping", num(o.passive_damping).c_str());
        break;
      case JointRole::kOther:
        j->SetAttribute("armature", "0.05");
        j->SetAttribute("damping", "1");
        break;
    }
  }
  for (auto* g = body->FirstChildElement("geom"); g; g = g->NextSiblingElement("geom")) {
    g->SetAttribute("contype", bits.contype);
    g->SetAttribute("conaffinity", bits.conaffinity);
    g->SetAttribute("group", "1");
    if (wheel) {
      g->SetAttribute("friction", (num(o.wheel_friction) + " 0.005 0.0001").c_str());
      const char* type = g->Attribute("type");
      if (o.sphere_wheels && type && std::string(type) == "cylinder") {
        std::istringstream size(g->Attribute("size") ? g->Attribute("size") : "");
        double r = 0;
        size >> r;
        g->SetAttribute("type", "sphere");
        g->SetAttribute("size", num(r).c_str());
        g->DeleteAttribute("quat");
      }
    }
  }
  if (wheel)  // after the geoms became spheres: the wheel's actuator learns its rolling radius
    for (auto& a : *actuators)
      if (!a.position && a.wheel_radius_m == 0.0 && body->FirstChildElement("joint") &&
          a.joint == body->FirstChildElement("joint")->Attribute("name"))
        a.wheel_radius_m = wheelRadius(body);
  for (auto* c = body->FirstChildElement("body"); c; c = c->NextSiblingElement("body")) tuneBody(c, o, bits, actuators);
}

// Every wheel contact takes the surface's friction and softness (the wheel geom's priority makes its values the
// contact's). Dry concrete leaves the geoms as they were.
void applyGround(tinyxml2::XMLElement* body, const SceneOptions& o) {
  if (o.ground == Ground::kDryConcrete) return;
  const GroundContact c = groundContact(o.ground);
  const char* bname = body->Attribute("name");
  if (bname && isWheelBody(bname))
    for (auto* g = body->FirstChildElement("geom"); g; g = g->NextSiblingElement("geom")) {
      g->SetAttribute("priority", "1");
      g->SetAttribute("friction", (num(c.friction) + " 0.005 0.0001").c_str());
      g->SetAttribute("solref", (num(c.solref_timeconst_s) + " " + num(c.solref_dampratio)).c_str());
      g->SetAttribute("solimp", (num(c.solimp_dmin) + " " + num(c.solimp_dmax) + " " + num(c.solimp_width_m)).c_str());
    }
  for (auto* b = body->FirstChildElement("body"); b; b = b->NextSiblingElement("body")) applyGround(b, o);
}

// The body below `body` that carries the joint named `joint`, or null.
tinyxml2::XMLElement* bodyWithJoint(tinyxml2::XMLElement* body, const std::string& joint) {
  for (auto* j = body->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    if (j->Attribute("name") && joint == j->Attribute("name")) return body;
  for (auto* b = body->FirstChildElement("body"); b; b = b->NextSiblingElement("body"))
    if (auto* found = bodyWithJoint(b, joint)) return found;
  return nullptr;
}

// A sprung passive hinge between the robot's frame and each drive module with suspension travel: the module's
// body (its steering body, else its wheel body) turns about an axis along y through a pivot `arm` ahead of it.
void addSuspension(tinyxml2::XMLElement* root, const RobotSpawn& r, double mass, int wheels, const SceneOptions& o) {
  const std::string p = r.name.empty() ? "" : r.name + "/";
  for (size_t i = 0; i < r.suspension_rad.size(); ++i) {
    const double travel = r.suspension_rad[i];
    if (!(travel > 0.0)) continue;
    const std::string n = std::to_string(i);
    auto* module = bodyWithJoint(root, p + "steering" + n);
    if (!module) module = bodyWithJoint(root, p + "wheel" + n);
    if (!module || module == root)
      throw ModelError("robot " + r.name + ": drive " + n + " has suspension but no module body");
    // Static load of one module on the arm, the spring sagging `suspension_sag` of the travel under it.
    const double share = mass / std::max(wheels, 1), arm = o.suspension_arm_m;
    const double stiffness = share * 9.81 * arm / (o.suspension_sag * travel);
    const double damping = 2.0 * o.suspension_damping_ratio * std::sqrt(stiffness * share * arm * arm);
    auto* j = module->GetDocument()->NewElement("joint");
    j->SetAttribute("name", (p + "suspension" + n).c_str());
    j->SetAttribute("type", "hinge");
    j->SetAttribute("pos", (num(arm) + " 0 0").c_str());
    j->SetAttribute("axis", "0 1 0");
    j->SetAttribute("range", (num(-travel) + " " + num(travel)).c_str());
    j->SetAttribute("limited", "true");
    j->SetAttribute("stiffness", num(stiffness).c_str());
    j->SetAttribute("damping", num(damping).c_str());
    j->SetAttribute("armature", "0.05");
    auto* first = module->FirstChildElement("joint");
    if (first && first->PreviousSibling())
      module->InsertAfterChild(first->PreviousSibling(), j);
    else if (first)
      module->InsertFirstChild(j);
    else
      module->InsertEndChild(j);
  }
}

}  // namespace

JointRole jointRole(const std::string& n) {
  static const std::regex steering("steering[0-9]+"), wheel("wheel[0-9]+"),
      passive("(caster[0-9]+_(swivel|wheel)|passive_wheel[0-9]+)");
  if (std::regex_match(n, steering)) return JointRole::kSteering;
  if (std::regex_match(n, wheel)) return JointRole::kWheel;
  if (std::regex_match(n, passive)) return JointRole::kPassive;
  return JointRole::kOther;
}

std::string composeScene(const WorldDescription& world, const std::vector<RobotSpawn>& robots, const SceneOptions& o) {
  std::ostringstream bodies, assets, acts;
  for (const auto& r : robots) {
    tinyxml2::XMLDocument doc;
    if (doc.Parse(r.mjcf.c_str(), r.mjcf.size()) != tinyxml2::XML_SUCCESS)
      throw ModelError("robot " + r.name + ": its MJCF is not XML: " + doc.ErrorStr());
    auto* mj = doc.FirstChildElement("mujoco");
    auto* wb = mj ? mj->FirstChildElement("worldbody") : nullptr;
    if (!wb) throw ModelError("robot " + r.name + ": its MJCF has no worldbody");
    if (auto* a = mj->FirstChildElement("asset"))
      for (auto* e = a->FirstChildElement(); e; e = e->NextSiblingElement()) {
        tinyxml2::XMLPrinter p(nullptr, true);
        e->Accept(&p);
        assets << p.CStr() << "\n";
      }
    std::vector<Actuator> actuators;
    double mass = 0.0;
    int roots = 0;
    for (auto* b = wb->FirstChildElement("body"); b; b = b->NextSiblingElement("body")) {
      ++roots;
      if (!b->Attribute("name") || r.root_link != b->Attribute("name"))
        throw ModelError("robot " + r.name + ": expected root body " + r.root_link);
      b->SetAttribute("pos", (num(r.x) + " " + num(r.y) + " " + num(world.spawn_z + r.z)).c_str());
      const Eigen::Quaterniond q(Eigen::AngleAxisd(r.yaw, Eigen::Vector3d::UnitZ()));
      b->SetAttribute("quat", (num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z())).c_str());
      tuneBody(b, o, robotBits(static_cast<size_t>(&r - robots.data()), robots.size()), &actuators);
      applyGround(b, o);
      mass += treeMass(b);
      int driven = 0;
      for (const auto& a : actuators) driven += a.position ? 0 : 1;
      addSuspension(b, r, treeMass(b), driven, o);
      tinyxml2::XMLPrinter p(nullptr, true);
      b->Accept(&p);
      bodies << p.CStr() << "\n";
    }
    if (roots != 1) throw ModelError("robot " + r.name + ": its MJCF must have exactly one root body");
    int wheels = 0;
    for (const auto& a : actuators) wheels += a.position ? 0 : 1;
    for (const auto& a : actuators) {
      // Drive torque limit: what the robot's share of weight on this wheel needs to climb the design slope at
      // the design acceleration. Applied per step by Simulation (the actuator's user value).
      const double torque_limit =
          o.wheel_torque_limit && wheels > 0
              ? mass / wheels * a.wheel_radius_m *
                    (9.81 * std::sin(o.wheel_design_slope_deg * M_PI / 180.0) + o.wheel_design_accel_mps2)
              : 0.0;
      if (a.position)
        acts << "<position name=\"" << a.joint << "\" joint=\"" << a.joint << "\" kp=\"" << o.steering_kp
             << "\" forcelimited=\"true\" forcerange=\"" << -o.steering_torque_max << " " << o.steering_torque_max
             << "\"/>\n";
      else
        acts << "<motor name=\"" << a.joint << "\" joint=\"" << a.joint << "\" gear=\"" << o.wheel_kv
             << "\" forcelimited=\"true\" forcerange=\"" << -o.wheel_torque_max << " " << o.wheel_torque_max
             << "\" user=\"" << torque_limit << "\"/>\n";
    }
  }
  std::ostringstream xml;
  xml << "<mujoco model=\"" << world.name << "\">\n"
      << "<compiler angle=\"radian\" autolimits=\"true\"/>\n"
      << "<option timestep=\"" << o.timestep_s << "\" integrator=\"Euler\"/>\n"
      << "<size njmax=\"" << 2000 + 400 * robots.size() << "\" nconmax=\"" << 500 + 100 * robots.size()
      << "\" nuser_actuator=\"1\"/>\n"
      << "<visual><global offwidth=\"" << o.camera_max_width << "\" offheight=\"" << o.camera_max_height
      << "\"/><quality offsamples=\"0\" numslices=\"" << o.render_slices << "\" numstacks=\""
      << std::max(8, o.render_slices / 2) << "\"/></visual>\n"
      << "<default><geom contype=\"1\" conaffinity=\"3\" friction=\"1 0.005 0.0001\"/></default>\n"
      << "<asset>\n"
      << assets.str() << "</asset>\n"
      << "<worldbody>\n"
      << world.worldbody << bodies.str() << "</worldbody>\n"
      << "<actuator>\n"
      << acts.str() << "</actuator>\n"
      << "</mujoco>\n";
  return xml.str();
}

}  // namespace thorvald_sim
