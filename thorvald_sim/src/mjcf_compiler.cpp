#include "thorvald_sim/mjcf_compiler.h"

#include <tinyxml2.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>

namespace thorvald_sim {

namespace {

// MuJoCo's XML loader and mj_saveLastXML keep global state.
std::mutex& compilerMutex() {
  static std::mutex m;
  return m;
}

struct VfsDeleter {
  void operator()(mjVFS* v) const {
    mj_deleteVFS(v);
    delete v;
  }
};

}  // namespace

ModelPtr compileXml(const std::string& xml, const std::string& what) {
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  const char* name = "model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    throw ModelError(what + ": cannot hold the model text in MuJoCo's virtual file system");
  const int idx = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[idx], xml.data(), xml.size());
  char error[1000] = "";
  std::lock_guard<std::mutex> lock(compilerMutex());
  mjModel* m = mj_loadXML(name, vfs.get(), error, sizeof(error));
  if (!m) throw ModelError(what + ": MuJoCo refused the model: " + error);
  return ModelPtr(m);
}

std::string prepareUrdf(const std::string& urdf, std::string* root_link) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(urdf.c_str(), urdf.size()) != tinyxml2::XML_SUCCESS)
    throw ModelError(std::string("robot_description is not XML: ") + doc.ErrorStr());
  tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw ModelError("robot_description has no <robot> element");
  std::set<std::string> links, children;
  for (auto* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
    if (l->Attribute("name")) links.insert(l->Attribute("name"));
  for (auto* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    auto* c = j->FirstChildElement("child");
    if (c && c->Attribute("link")) children.insert(c->Attribute("link"));
  }
  std::string root;
  for (const auto& l : links)
    if (!children.count(l)) {
      if (!root.empty()) throw ModelError("robot_description has two root links: " + root + " and " + l);
      root = l;
    }
  if (root.empty()) throw ModelError("robot_description has no root link");
  if (root == "world") throw ModelError("robot_description is already attached to a link named world");
  if (root_link) *root_link = root;
  // Drop any <mujoco> block the URDF carries and add ours.
  while (auto* old = robot->FirstChildElement("mujoco")) robot->DeleteChild(old);
  auto* mujoco = doc.NewElement("mujoco");
  auto* compiler = doc.NewElement("compiler");
  compiler->SetAttribute("discardvisual", "true");
  compiler->SetAttribute("fusestatic", "false");
  compiler->SetAttribute("strippath", "false");
  mujoco->InsertEndChild(compiler);
  robot->InsertFirstChild(mujoco);
  auto* world = doc.NewElement("link");
  world->SetAttribute("name", "world");
  robot->InsertAfterChild(mujoco, world);
  const std::string prefix = root.size() > 9 && root.compare(root.size() - 9, 9, "base_link") == 0
                                 ? root.substr(0, root.size() - 9)
                                 : std::string();
  auto* joint = doc.NewElement("joint");
  joint->SetAttribute("name", (prefix + "root").c_str());
  joint->SetAttribute("type", "floating");
  auto* parent = doc.NewElement("parent");
  parent->SetAttribute("link", "world");
  auto* child = doc.NewElement("child");
  child->SetAttribute("link", root.c_str());
  joint->InsertEndChild(parent);
  joint->InsertEndChild(child);
  robot->InsertAfterChild(world, joint);
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

std::string urdfToMjcf(const std::string& urdf, std::string* root_link) {
  const std::string prepared = prepareUrdf(urdf, root_link);
  char path[] = "/tmp/thorvald_sim_XXXXXX";
  const int fd = mkstemp(path);
  if (fd < 0) throw ModelError("cannot create a temporary file for mj_saveLastXML");
  close(fd);
  char error[1000] = "";
  int ok;
  {
    std::lock_guard<std::mutex> lock(compilerMutex());
    // mj_saveLastXML writes the last XML loaded by anyone: load and save under one lock.
    std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
    mj_defaultVFS(vfs.get());
    mj_makeEmptyFileVFS(vfs.get(), "robot.urdf", static_cast<int>(prepared.size()));
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), "robot.urdf")], prepared.data(), prepared.size());
    mjModel* again = mj_loadXML("robot.urdf", vfs.get(), error, sizeof(error));
    ok = again && mj_saveLastXML(path, again, error, sizeof(error));
    if (again) mj_deleteModel(again);
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::remove(path);
  if (!ok) throw ModelError(std::string("robot_description: MuJoCo refused the URDF: ") + error);
  return text.str();
}

}  // namespace thorvald_sim
