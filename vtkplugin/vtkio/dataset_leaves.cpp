#include "rayscope_vtkio/dataset_leaves.h"

#include "vtkCompositeDataDisplayAttributes.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"

namespace rayscope_vtkio {

namespace {

// The walk of the tree in pre-order, numbering nodes as vtkDataObjectTreeIterator
// does, with the display attributes inherited from parent to child as
// vtkCompositePolyDataMapper2 inherits them.
class LeafWalk {
 public:
  LeafWalk(vtkCompositeDataDisplayAttributes* attributes, DatasetLeaves& out)
      : attributes_(attributes), out_(out) {}

  void visit(vtkDataObject* node, vtkInformation* meta, DatasetLeaf inherited, bool visible) {
    const unsigned flat = next_++;
    if (!node) return;
    if (meta && meta->Has(vtkCompositeDataSet::NAME()))
      inherited.name = meta->Get(vtkCompositeDataSet::NAME());
    if (attributes_) {
      if (attributes_->HasBlockVisibility(node)) visible = attributes_->GetBlockVisibility(node);
      if (attributes_->HasBlockColor(node)) {
        inherited.has_color = true;
        attributes_->GetBlockColor(node, inherited.color);
      }
      if (attributes_->HasBlockOpacity(node)) {
        inherited.has_opacity = true;
        inherited.opacity = attributes_->GetBlockOpacity(node);
      }
    }
    if (auto* mb = vtkMultiBlockDataSet::SafeDownCast(node)) {
      for (unsigned i = 0; i < mb->GetNumberOfBlocks(); ++i)
        visit(mb->GetBlock(i), mb->HasMetaData(i) ? mb->GetMetaData(i) : nullptr, inherited,
              visible);
    } else if (auto* pd = vtkPartitionedDataSet::SafeDownCast(node)) {
      for (unsigned i = 0; i < pd->GetNumberOfPartitions(); ++i)
        visit(pd->GetPartitionAsDataObject(i), pd->HasMetaData(i) ? pd->GetMetaData(i) : nullptr,
              inherited, visible);
    } else if (auto* pc = vtkPartitionedDataSetCollection::SafeDownCast(node)) {
      for (unsigned i = 0; i < pc->GetNumberOfPartitionedDataSets(); ++i)
        visit(pc->GetPartitionedDataSet(i), pc->HasMetaData(i) ? pc->GetMetaData(i) : nullptr,
              inherited, visible);
    } else if (auto* ds = vtkDataSet::SafeDownCast(node)) {
      if (!visible) return;
      inherited.data = ds;
      inherited.flat_index = flat;
      out_.leaves.push_back(inherited);
    } else if (visible) {
      out_.skipped.push_back("block " + std::to_string(flat) + " (" + node->GetClassName() + ")");
    }
  }

 private:
  vtkCompositeDataDisplayAttributes* attributes_;
  DatasetLeaves& out_;
  unsigned next_ = 0;
};

}  // namespace

DatasetLeaves dataset_leaves(vtkDataObject* data, vtkCompositeDataDisplayAttributes* attributes) {
  DatasetLeaves out;
  LeafWalk(attributes, out).visit(data, nullptr, DatasetLeaf{}, true);
  return out;
}

std::vector<vtkDataSet*> leaf_datasets(const std::vector<DatasetLeaf>& leaves) {
  std::vector<vtkDataSet*> out;
  out.reserve(leaves.size());
  for (const DatasetLeaf& l : leaves) out.push_back(l.data);
  return out;
}

}  // namespace rayscope_vtkio
