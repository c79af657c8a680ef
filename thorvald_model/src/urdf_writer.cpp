#include "thorvald_model/urdf_writer.h"

#include <tinyxml2.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace thorvald_model {

namespace {

using tinyxml2::XMLDocument;
using tinyxml2::XMLElement;

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

std::string triple(const Eigen::Vector3d& v) { return number(v.x()) + " " + number(v.y()) + " " + number(v.z()); }

XMLElement* child(XMLElement* parent, const char* name) {
  XMLElement* e = parent->GetDocument()->NewElement(name);
  parent->InsertEndChild(e);
  return e;
}

void origin(XMLElement* parent, const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy) {
  XMLElement* o = child(parent, "origin");
  o->SetAttribute("xyz", triple(xyz).c_str());
  o->SetAttribute("rpy", triple(rpy).c_str());
}

void geometry(XMLElement* parent, const Shape& s) {
  XMLElement* g = child(child(parent, "geometry"), s.kind == Shape::Kind::kBox ? "box" : "cylinder");
  if (s.kind == Shape::Kind::kBox) {
    g->SetAttribute("size", triple(s.size_m).c_str());
  } else {
    g->SetAttribute("radius", number(s.radius_m).c_str());
    g->SetAttribute("length", number(s.length_m).c_str());
  }
}

const std::map<std::string, std::string>& materials() {
  static const std::map<std::string, std::string> colours = {{"aluminium", "0.75 0.76 0.78 1"},
                                                             {"black", "0.08 0.08 0.08 1"},
                                                             {"grey", "0.45 0.46 0.48 1"},
                                                             {"orange", "0.93 0.45 0.05 1"}};
  return colours;
}

void writeLink(XMLElement* robot, const Link& link, const std::string& material_prefix) {
  XMLElement* l = child(robot, "link");
  l->SetAttribute("name", link.name.c_str());
  if (link.inertial.mass_kg > 0.0) {
    XMLElement* in = child(l, "inertial");
    origin(in, link.inertial.com_m, Eigen::Vector3d::Zero());
    child(in, "mass")->SetAttribute("value", number(link.inertial.mass_kg).c_str());
    XMLElement* i = child(in, "inertia");
    const Eigen::Matrix3d& m = link.inertial.inertia;
    i->SetAttribute("ixx", number(m(0, 0)).c_str());
    i->SetAttribute("ixy", number(m(0, 1)).c_str());
    i->SetAttribute("ixz", number(m(0, 2)).c_str());
    i->SetAttribute("iyy", number(m(1, 1)).c_str());
    i->SetAttribute("iyz", number(m(1, 2)).c_str());
    i->SetAttribute("izz", number(m(2, 2)).c_str());
  }
  for (const auto& s : link.shapes) {
    XMLElement* v = child(l, "visual");
    origin(v, s.xyz_m, s.rpy_rad);
    geometry(v, s);
    child(v, "material")->SetAttribute("name", (material_prefix + s.material).c_str());
    XMLElement* c = child(l, "collision");
    origin(c, s.xyz_m, s.rpy_rad);
    geometry(c, s);
  }
}

void writeJoint(XMLElement* robot, const Joint& j) {
  XMLElement* e = child(robot, "joint");
  e->SetAttribute("name", j.name.c_str());
  e->SetAttribute("type", j.type.c_str());
  child(e, "parent")->SetAttribute("link", j.parent.c_str());
  child(e, "child")->SetAttribute("link", j.child.c_str());
  origin(e, j.xyz_m, j.rpy_rad);
  if (j.type == "revolute" || j.type == "continuous") {
    child(e, "axis")->SetAttribute("xyz", triple(j.axis).c_str());
    XMLElement* limit = child(e, "limit");
    if (j.type == "revolute") {
      limit->SetAttribute("lower", number(j.lower_rad).c_str());
      limit->SetAttribute("upper", number(j.upper_rad).c_str());
    }
    limit->SetAttribute("effort", number(j.effort).c_str());
    limit->SetAttribute("velocity", number(j.velocity).c_str());
    XMLElement* dyn = child(e, "dynamics");
    dyn->SetAttribute("damping", "0.1");
    dyn->SetAttribute("friction", "0");
  }
}

void prefixAttribute(XMLElement* e, const char* attribute, const std::string& prefix) {
  const char* value = e->Attribute(attribute);
  if (prefix.empty() || value == nullptr) return;
  const std::string v(value);
  if (v.rfind(prefix + "/", 0) == 0) return;
  e->SetAttribute(attribute, (prefix + "/" + v).c_str());
}

void mergeFragment(XMLElement* robot, const UrdfFragment& fragment, const std::string& prefix) {
  XMLDocument doc;
  if (doc.Parse(fragment.text.c_str()) != tinyxml2::XML_SUCCESS) {
    throw FragmentError(fragment.source + ": not readable XML: " + (doc.ErrorStr() ? doc.ErrorStr() : ""));
  }
  XMLElement* root = doc.RootElement();
  if (root == nullptr || std::string(root->Name()) != "robot") {
    throw FragmentError(fragment.source + ": expected a <robot> element holding the links and joints to add");
  }
  for (XMLElement* e = root->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
    const std::string tag = e->Name();
    if (tag == "link" || tag == "joint") prefixAttribute(e, "name", prefix);
    if (tag == "joint") {
      for (const char* end : {"parent", "child"}) {
        XMLElement* p = e->FirstChildElement(end);
        if (p == nullptr || p->Attribute("link") == nullptr) {
          throw FragmentError(fragment.source + ": joint '" + (e->Attribute("name") ? e->Attribute("name") : "") +
                              "' has no <" + end + " link=\"...\"/>");
        }
        prefixAttribute(p, "link", prefix);
      }
    }
    robot->InsertEndChild(e->DeepClone(robot->GetDocument()));
  }
}

/// Checks the merged tree: unique names, joints between existing links, one parent per link.
void checkTree(XMLElement* robot) {
  std::set<std::string> links, joints;
  std::map<std::string, std::string> parent_of;
  for (XMLElement* e = robot->FirstChildElement("link"); e; e = e->NextSiblingElement("link")) {
    const char* n = e->Attribute("name");
    if (n == nullptr) throw FragmentError("a <link> without a name");
    if (!links.insert(n).second) throw FragmentError("link '" + std::string(n) + "' is defined twice");
  }
  for (XMLElement* e = robot->FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) {
    const std::string n = e->Attribute("name") ? e->Attribute("name") : "";
    if (!joints.insert(n).second) throw FragmentError("joint '" + n + "' is defined twice");
    const std::string parent = e->FirstChildElement("parent")->Attribute("link");
    const std::string c = e->FirstChildElement("child")->Attribute("link");
    for (const auto& l : {parent, c}) {
      if (!links.count(l)) throw FragmentError("joint '" + n + "' names link '" + l + "', which does not exist");
    }
    if (!parent_of.emplace(c, n).second) {
      throw FragmentError("link '" + c + "' has two parent joints: '" + parent_of[c] + "' and '" + n + "'");
    }
  }
}

}  // namespace

std::string writeUrdf(const UrdfTree& tree, const std::vector<UrdfFragment>& fragments, const WriteOptions& options) {
  XMLDocument doc;
  doc.InsertEndChild(doc.NewDeclaration());
  doc.InsertEndChild(doc.NewComment(" Generated by thorvald_model/urdf_generator from a Thorvald robot file. "));
  XMLElement* robot = doc.NewElement("robot");
  doc.InsertEndChild(robot);
  robot->SetAttribute("name", tree.robot_name.c_str());
  if (options.mujoco_compiler) {
    XMLElement* c = child(child(robot, "mujoco"), "compiler");
    c->SetAttribute("discardvisual", "true");
    c->SetAttribute("fusestatic", "false");
    c->SetAttribute("balanceinertia", "false");
  }
  const std::string material_prefix = options.tf_prefix.empty() ? "thorvald_" : options.tf_prefix + "/thorvald_";
  for (const auto& [name, rgba] : materials()) {
    XMLElement* m = child(robot, "material");
    m->SetAttribute("name", (material_prefix + name).c_str());
    child(m, "color")->SetAttribute("rgba", rgba.c_str());
  }
  for (const auto& link : tree.links) writeLink(robot, link, material_prefix);
  for (const auto& j : tree.joints) writeJoint(robot, j);
  for (const auto& f : fragments) mergeFragment(robot, f, options.tf_prefix);
  checkTree(robot);
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

}  // namespace thorvald_model
