// The structures' name table (rayscope/accel/accel_kind.h): every kind has one
// row, its words and numbers are unique and round-trip, and the ParaView
// plugin's drop-downs list exactly the table's labels under its numbers.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "rayscope/accel/accel_kind.h"

using namespace rayscope;

TEST(AccelKindTable, EveryKindHasOneRowWithUniqueNames) {
  // The enumerators are 0 .. Spheres: each has exactly one row.
  std::set<int> kinds, vtk_ids;
  std::set<std::string> words, labels;
  for (const AccelKindName& n : kAccelKindNames) {
    EXPECT_TRUE(kinds.insert(int(n.kind)).second) << n.word;
    EXPECT_TRUE(vtk_ids.insert(n.vtk_id).second) << n.word;
    EXPECT_TRUE(words.insert(n.word).second) << n.word;
    EXPECT_TRUE(labels.insert(n.label).second) << n.word;
    EXPECT_NE(n.storages & (1u << unsigned(PrimStorage::EveryCell)), 0u)
        << n.word << ": every structure takes the default storage";
  }
  EXPECT_EQ(kinds.size(), size_t(AccelKind::Spheres) + 1);
  EXPECT_EQ(kAccelKinds.size(), kinds.size());
}

TEST(AccelKindTable, WordsAndVtkIdsRoundTrip) {
  for (AccelKind k : kAccelKinds) {
    AccelKind parsed{};
    ASSERT_TRUE(parse_accel_kind(to_string(k), parsed)) << to_string(k);
    EXPECT_EQ(parsed, k);
    AccelKind by_id{};
    ASSERT_TRUE(accel_kind_of_vtk_id(accel_kind_name(k).vtk_id, by_id)) << to_string(k);
    EXPECT_EQ(by_id, k);
  }
  AccelKind k{};
  EXPECT_FALSE(parse_accel_kind("BVH", k));
  EXPECT_FALSE(parse_accel_kind("", k));
  EXPECT_FALSE(accel_kind_of_vtk_id(-1, k));
  EXPECT_FALSE(accel_kind_of_vtk_id(int(std::size(kAccelKindNames)), k));
}

TEST(AccelKindTable, StorageRuleFollowsTheTable) {
  for (AccelKind k : kAccelKinds)
    for (PrimStorage s : kPrimStorages) {
      const bool takes = (accel_kind_name(k).storages >> unsigned(s)) & 1u;
      EXPECT_EQ(accel_storage_error(k, s).empty(), takes) << to_string(k) << " " << to_string(s);
    }
  EXPECT_EQ(accel_storage_error(AccelKind::Bsp, PrimStorage::Split), "");
  EXPECT_NE(accel_storage_error(AccelKind::Octree, PrimStorage::Split), "");
  EXPECT_NE(accel_storage_error(AccelKind::Bvh, PrimStorage::SmallestCell), "");
}

// Every "Accel" property of the ParaView plugin lists the table's labels under
// the table's numbers, no more and no less.
TEST(AccelKindTable, ParaViewLabelsAreTheTables) {
  const std::string path =
      std::string(RAYSCOPE_SOURCE_DIR) + "/vtkplugin/paraview/RayScope/RayScope.xml";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  std::map<int, std::string> expected;
  for (const AccelKindName& n : kAccelKindNames) expected[n.vtk_id] = n.label;

  const std::regex property(R"re(<IntVectorProperty name="Accel"[\s\S]*?</IntVectorProperty>)re");
  const std::regex entry(R"re(<Entry value="(\d+)" text="([^"]*)"/>)re");
  int properties = 0;
  for (auto p = std::sregex_iterator(xml.begin(), xml.end(), property); p != std::sregex_iterator();
       ++p) {
    ++properties;
    const std::string body = p->str();
    std::map<int, std::string> found;
    for (auto e = std::sregex_iterator(body.begin(), body.end(), entry);
         e != std::sregex_iterator(); ++e)
      found[std::stoi((*e)[1].str())] = (*e)[2].str();
    EXPECT_EQ(found, expected);
  }
  EXPECT_GE(properties, 1) << "no Accel property in " << path;
}
