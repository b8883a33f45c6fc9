#include "GridFreePieceGather.h"

#include "vtkAppendFilter.h"
#include "vtkAppendPolyData.h"
#include "vtkCharArray.h"
#include "vtkCommunicator.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataObjectTree.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMatrix3x3.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <climits>
#include <cstring>
#include <vector>

namespace gridfree
{
void RequestPiece(vtkInformation* info, int piece, int pieces)
{
  if (!info)
  {
    return;
  }
  // Only the piece: structured data gets the extent the executive derives
  // from it, as every other consumer of the same output asks in a parallel
  // run. A different request (another extent, or the whole) would make a
  // collective upstream filter (Resample To Image, D3) run on some ranks only,
  // and the ranks would wait for each other forever.
  info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), piece);
  info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), pieces);
  info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
}

namespace
{
// What every rank tells the others about its piece before any data moves.
enum PieceStatus : unsigned long long
{
  PIECE_OK = 0,
  PIECE_EMPTY = 1,
  PIECE_UNMARSHALABLE = 2,
};
struct PieceHeader
{
  unsigned long long Length = 0;
  unsigned long long Hash = 0;
  unsigned long long Status = PIECE_EMPTY;
  unsigned long long IsImage = 0; // the bytes end with an ImageGeometry
};
constexpr int HeaderWords = 4;

// The communicator's serialization (the legacy VTK format) writes an
// image's origin and spacing as text with six significant digits, and no
// direction: images carry their exact geometry after the serialized bytes.
struct ImageGeometry
{
  long long Extent[6];
  double Origin[3];
  double Spacing[3];
  double Direction[9];

  explicit ImageGeometry(vtkImageData* image = nullptr)
  {
    std::memset(this, 0, sizeof(*this));
    if (image)
    {
      for (int k = 0; k < 6; ++k)
      {
        this->Extent[k] = image->GetExtent()[k];
      }
      std::copy_n(image->GetOrigin(), 3, this->Origin);
      std::copy_n(image->GetSpacing(), 3, this->Spacing);
      std::copy_n(image->GetDirectionMatrix()->GetData(), 9, this->Direction);
    }
  }
  void ApplyTo(vtkImageData* image) const
  {
    int extent[6];
    for (int k = 0; k < 6; ++k)
    {
      extent[k] = static_cast<int>(this->Extent[k]);
    }
    image->SetExtent(extent);
    image->SetOrigin(this->Origin);
    image->SetSpacing(this->Spacing);
    image->SetDirectionMatrix(this->Direction);
  }
};

// FNV-1a over 8-byte words: the bytes' identity, not a secure hash.
std::uint64_t HashBytes(const char* bytes, std::size_t length)
{
  std::uint64_t h = 14695981039346656037ULL;
  const std::uint64_t prime = 1099511628211ULL;
  std::size_t i = 0;
  for (; i + 8 <= length; i += 8)
  {
    std::uint64_t word;
    std::memcpy(&word, bytes + i, 8);
    h = (h ^ word) * prime;
  }
  for (; i < length; ++i)
  {
    h = (h ^ static_cast<unsigned char>(bytes[i])) * prime;
  }
  return h ^ length;
}

bool IsEmpty(vtkDataObject* data)
{
  if (!data)
  {
    return true;
  }
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    return composite->GetNumberOfPoints() == 0;
  }
  auto* dataset = vtkDataSet::SafeDownCast(data);
  return !dataset || (dataset->GetNumberOfPoints() == 0 && dataset->GetNumberOfCells() == 0);
}

bool SameGrid(vtkImageData* a, vtkImageData* b)
{
  for (int k = 0; k < 3; ++k)
  {
    if (a->GetOrigin()[k] != b->GetOrigin()[k] || a->GetSpacing()[k] != b->GetSpacing()[k])
    {
      return false;
    }
  }
  for (int k = 0; k < 9; ++k)
  {
    if (a->GetDirectionMatrix()->GetData()[k] != b->GetDirectionMatrix()->GetData()[k])
    {
      return false;
    }
  }
  return true;
}

// Image pieces are blocks of one grid: the whole is their union, each point
// array copied block by block (blocks overlap on shared faces, with equal
// values there). Blocks that leave a hole in their union are refused: a
// zero-filled hole would silently change the solution.
vtkSmartPointer<vtkDataObject> MergeImages(
  const std::vector<vtkImageData*>& pieces, std::string& reason)
{
  vtkImageData* first = pieces.front();
  int whole[6] = { INT_MAX, INT_MIN, INT_MAX, INT_MIN, INT_MAX, INT_MIN };
  for (vtkImageData* piece : pieces)
  {
    if (!SameGrid(first, piece))
    {
      reason = "the image pieces of different ranks lie on different grids (origin, spacing "
               "or direction)";
      return nullptr;
    }
    const int* e = piece->GetExtent();
    for (int k = 0; k < 3; ++k)
    {
      whole[2 * k] = std::min(whole[2 * k], e[2 * k]);
      whole[2 * k + 1] = std::max(whole[2 * k + 1], e[2 * k + 1]);
    }
  }
  vtkNew<vtkImageData> image;
  image->SetExtent(whole);
  image->SetOrigin(first->GetOrigin());
  image->SetSpacing(first->GetSpacing());
  image->SetDirectionMatrix(first->GetDirectionMatrix());
  image->GetFieldData()->ShallowCopy(first->GetFieldData());
  const vtkIdType nx = whole[1] - whole[0] + 1;
  const vtkIdType ny = whole[3] - whole[2] + 1;
  std::vector<char> covered(static_cast<std::size_t>(image->GetNumberOfPoints()), 0);
  for (vtkImageData* piece : pieces)
  {
    const int* e = piece->GetExtent();
    for (int k = e[4]; k <= e[5]; ++k)
    {
      for (int j = e[2]; j <= e[3]; ++j)
      {
        const vtkIdType row = (e[0] - whole[0]) + nx * ((j - whole[2]) + ny * (k - whole[4]));
        std::fill_n(covered.begin() + row, e[1] - e[0] + 1, 1);
      }
    }
  }
  if (std::find(covered.begin(), covered.end(), 0) != covered.end())
  {
    reason = "the image pieces of the ranks leave holes in the extent they span (" +
      std::to_string(std::count(covered.begin(), covered.end(), 0)) + " points missing)";
    return nullptr;
  }
  vtkPointData* firstData = first->GetPointData();
  for (int a = 0; a < firstData->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* model = firstData->GetArray(a);
    if (!model || !model->GetName())
    {
      continue; // only named numeric arrays can be selected downstream
    }
    vtkSmartPointer<vtkDataArray> merged;
    merged.TakeReference(model->NewInstance());
    merged->SetName(model->GetName());
    merged->SetNumberOfComponents(model->GetNumberOfComponents());
    merged->SetNumberOfTuples(image->GetNumberOfPoints());
    for (vtkImageData* piece : pieces)
    {
      vtkDataArray* from = piece->GetPointData()->GetArray(model->GetName());
      if (!from || from->GetDataType() != model->GetDataType() ||
        from->GetNumberOfComponents() != model->GetNumberOfComponents())
      {
        reason = std::string("the image pieces of different ranks do not all have the point "
                             "array '") +
          model->GetName() + "' with the same type and components";
        return nullptr;
      }
      const int* e = piece->GetExtent();
      vtkIdType source = 0;
      for (int k = e[4]; k <= e[5]; ++k)
      {
        for (int j = e[2]; j <= e[3]; ++j)
        {
          vtkIdType target = (e[0] - whole[0]) + nx * ((j - whole[2]) + ny * (k - whole[4]));
          for (int i = e[0]; i <= e[1]; ++i, ++source, ++target)
          {
            merged->SetTuple(target, source, from);
          }
        }
      }
    }
    image->GetPointData()->AddArray(merged);
  }
  if (vtkDataArray* scalars = firstData->GetScalars())
  {
    if (scalars->GetName())
    {
      image->GetPointData()->SetActiveScalars(scalars->GetName());
    }
  }
  return image;
}

// Merges the pieces of one leaf (datasets of one kind), in rank order.
vtkSmartPointer<vtkDataObject> MergeDatasets(
  const std::vector<vtkDataObject*>& pieces, std::string& reason)
{
  if (pieces.empty())
  {
    return nullptr;
  }
  if (pieces.size() == 1)
  {
    return pieces.front();
  }
  std::vector<vtkPolyData*> polys;
  std::vector<vtkImageData*> images;
  for (vtkDataObject* piece : pieces)
  {
    if (auto* poly = vtkPolyData::SafeDownCast(piece))
    {
      polys.push_back(poly);
    }
    else if (auto* image = vtkImageData::SafeDownCast(piece))
    {
      images.push_back(image);
    }
    else if (!vtkDataSet::SafeDownCast(piece))
    {
      reason = std::string("a piece is a ") + piece->GetClassName() + ", not a dataset";
      return nullptr;
    }
  }
  if (polys.size() == pieces.size())
  {
    vtkNew<vtkAppendPolyData> append;
    for (vtkPolyData* poly : polys)
    {
      append->AddInputData(poly);
    }
    append->Update();
    return append->GetOutput();
  }
  if (images.size() == pieces.size())
  {
    return MergeImages(images, reason);
  }
  if (!polys.empty() && polys.size() < pieces.size())
  {
    reason = "the ranks hold pieces of different types (vtkPolyData and other datasets)";
    return nullptr;
  }
  // Other datasets (unstructured, rectilinear, structured grids): their cells.
  vtkNew<vtkAppendFilter> append;
  append->MergePointsOff();
  for (vtkDataObject* piece : pieces)
  {
    append->AddInputData(piece);
  }
  append->Update();
  return append->GetOutput();
}

// Composite pieces (a multiblock boundary) share one structure: each leaf is
// merged from that leaf of every piece.
vtkSmartPointer<vtkDataObject> MergeComposites(
  const std::vector<vtkDataObject*>& pieces, std::string& reason)
{
  std::vector<std::vector<vtkDataObject*>> leaves(pieces.size());
  for (std::size_t p = 0; p < pieces.size(); ++p)
  {
    auto* tree = vtkDataObjectTree::SafeDownCast(pieces[p]);
    if (!tree)
    {
      reason = "the ranks hold pieces of different types (composite and not)";
      return nullptr;
    }
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(tree->NewIterator());
    it->SkipEmptyNodesOff();
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      leaves[p].push_back(it->GetCurrentDataObject());
    }
    if (leaves[p].size() != leaves[0].size())
    {
      reason = "the composite pieces of different ranks have different numbers of blocks";
      return nullptr;
    }
  }
  auto* first = vtkDataObjectTree::SafeDownCast(pieces.front());
  vtkSmartPointer<vtkDataObjectTree> whole;
  whole.TakeReference(first->NewInstance());
  whole->CopyStructure(first);
  vtkSmartPointer<vtkCompositeDataIterator> it;
  it.TakeReference(first->NewIterator());
  it->SkipEmptyNodesOff();
  std::size_t leaf = 0;
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem(), ++leaf)
  {
    std::vector<vtkDataObject*> parts;
    for (const auto& pieceLeaves : leaves)
    {
      if (!IsEmpty(pieceLeaves[leaf]))
      {
        parts.push_back(pieceLeaves[leaf]);
      }
    }
    vtkSmartPointer<vtkDataObject> merged = MergeDatasets(parts, reason);
    if (!merged && !parts.empty())
    {
      return nullptr;
    }
    whole->SetDataSet(it, merged);
  }
  return whole;
}
} // namespace

bool GatherPieces(vtkMultiProcessController* controller, vtkDataObject* piece,
  GatheredPieces& out, std::string& reason)
{
  out = GatheredPieces();
  const int ranks = controller ? controller->GetNumberOfProcesses() : 1;
  const int rank = controller ? controller->GetLocalProcessId() : 0;

  // This rank's piece as bytes: what is sent, and what identifies it.
  vtkNew<vtkCharArray> bytes;
  PieceHeader mine;
  if (!IsEmpty(piece))
  {
    if (vtkCommunicator::MarshalDataObject(piece, bytes) == 0)
    {
      mine.Status = PIECE_UNMARSHALABLE;
    }
    else
    {
      if (auto* image = vtkImageData::SafeDownCast(piece))
      {
        const ImageGeometry geometry(image);
        const vtkIdType at = bytes->GetNumberOfValues();
        bytes->Resize(at + static_cast<vtkIdType>(sizeof(geometry)));
        bytes->SetNumberOfValues(at + static_cast<vtkIdType>(sizeof(geometry)));
        std::memcpy(bytes->GetPointer(at), &geometry, sizeof(geometry));
        mine.IsImage = 1;
      }
      mine.Status = PIECE_OK;
      mine.Length = static_cast<unsigned long long>(bytes->GetNumberOfValues());
      mine.Hash = HashBytes(bytes->GetPointer(0), static_cast<std::size_t>(mine.Length));
    }
  }

  std::vector<unsigned long long> words(static_cast<std::size_t>(HeaderWords) * ranks);
  const unsigned long long send[HeaderWords] = { mine.Length, mine.Hash, mine.Status,
    mine.IsImage };
  if (ranks == 1)
  {
    std::copy(send, send + HeaderWords, words.begin());
  }
  else if (!controller->AllGather(send, words.data(), HeaderWords))
  {
    reason = "the ranks could not exchange the sizes of their pieces";
    return false;
  }
  std::vector<PieceHeader> headers(ranks);
  std::uint64_t signature = 14695981039346656037ULL;
  for (int r = 0; r < ranks; ++r)
  {
    headers[r].Length = words[HeaderWords * r];
    headers[r].Hash = words[HeaderWords * r + 1];
    headers[r].Status = words[HeaderWords * r + 2];
    headers[r].IsImage = words[HeaderWords * r + 3];
    signature = (signature ^ headers[r].Hash) * 1099511628211ULL;
    signature = (signature ^ headers[r].Length) * 1099511628211ULL;
    if (headers[r].Status == PIECE_UNMARSHALABLE)
    {
      reason = "rank " + std::to_string(r) + " holds a piece that cannot be sent (" +
        "a data type the communicator cannot serialize)";
      return false;
    }
  }
  out.Signature = signature;

  // Which ranks contribute: not empty, and not equal to a lower rank's piece.
  std::vector<bool> contributes(ranks, false);
  unsigned long long total = 0;
  for (int r = 0; r < ranks; ++r)
  {
    if (headers[r].Status != PIECE_OK)
    {
      continue;
    }
    bool copy = false;
    for (int q = 0; q < r && !copy; ++q)
    {
      copy = headers[q].Status == PIECE_OK && headers[q].Length == headers[r].Length &&
        headers[q].Hash == headers[r].Hash;
    }
    contributes[r] = !copy;
    out.ContributingRanks += copy ? 0 : 1;
    total += copy ? 0 : headers[r].Length;
  }
  if (out.ContributingRanks == 0)
  {
    return true; // nothing anywhere: the caller reports a missing input
  }
  // Every rank holds the same piece (an upstream that ignores piece requests
  // gave each the whole dataset): nothing needs to move.
  const int firstContributor =
    static_cast<int>(std::find(contributes.begin(), contributes.end(), true) - contributes.begin());
  const bool everyoneHoldsIt = [&] {
    for (int r = 0; r < ranks; ++r)
    {
      if (headers[r].Length != headers[firstContributor].Length ||
        headers[r].Hash != headers[firstContributor].Hash || headers[r].Status != PIECE_OK)
      {
        return false;
      }
    }
    return true;
  }();
  if (out.ContributingRanks == 1 && everyoneHoldsIt)
  {
    out.Whole = piece;
    return true;
  }
  if (total > static_cast<unsigned long long>(INT_MAX))
  {
    reason = "the pieces add up to " + std::to_string(total >> 20) +
      " MiB, more than the 2 GiB one exchange between ranks can carry";
    return false;
  }

  // Every rank receives every contributing piece.
  std::vector<vtkIdType> lengths(ranks, 0);
  std::vector<vtkIdType> offsets(ranks, 0);
  vtkIdType running = 0;
  for (int r = 0; r < ranks; ++r)
  {
    lengths[r] = contributes[r] ? static_cast<vtkIdType>(headers[r].Length) : 0;
    offsets[r] = running;
    running += lengths[r];
  }
  std::vector<char> received(static_cast<std::size_t>(std::max<vtkIdType>(running, 1)));
  if (ranks > 1 &&
    !controller->AllGatherV(bytes->GetNumberOfValues() > 0 ? bytes->GetPointer(0) : nullptr,
      received.data(), lengths[rank], lengths.data(), offsets.data()))
  {
    reason = "the ranks could not exchange their pieces";
    return false;
  }
  if (ranks == 1 && running > 0)
  {
    std::memcpy(received.data(), bytes->GetPointer(0), static_cast<std::size_t>(running));
  }

  std::vector<vtkSmartPointer<vtkDataObject>> kept;
  std::vector<vtkDataObject*> parts;
  for (int r = 0; r < ranks; ++r)
  {
    if (!contributes[r])
    {
      continue;
    }
    char* start = received.data() + offsets[r];
    vtkIdType length = lengths[r];
    ImageGeometry geometry;
    if (headers[r].IsImage)
    {
      length -= static_cast<vtkIdType>(sizeof(geometry));
      std::memcpy(&geometry, start + length, sizeof(geometry));
    }
    vtkNew<vtkCharArray> slice;
    slice->SetArray(start, length, 1); // borrowed, not freed
    vtkSmartPointer<vtkDataObject> object = vtkCommunicator::UnMarshalDataObject(slice);
    auto* image = vtkImageData::SafeDownCast(object);
    if (!object || (headers[r].IsImage != 0) != (image != nullptr))
    {
      reason = "the piece of rank " + std::to_string(r) + " could not be read back";
      return false;
    }
    if (image)
    {
      geometry.ApplyTo(image);
    }
    kept.push_back(object);
    parts.push_back(object);
  }
  out.Whole = vtkCompositeDataSet::SafeDownCast(parts.front()) ? MergeComposites(parts, reason)
                                                                : MergeDatasets(parts, reason);
  return out.Whole != nullptr;
}
} // namespace gridfree
