#include "vtkSoftBodyFrameCache.h"

//------------------------------------------------------------------------------
void vtkSoftBodyFrameCache::SetMemoryLimit(std::size_t bytes)
{
  this->MemoryLimit = bytes;
  this->EvictToLimit();
}

//------------------------------------------------------------------------------
std::size_t vtkSoftBodyFrameCache::SizeOf(const softbody::DynamicState& state)
{
  return sizeof(softbody::DynamicState) +
    (state.positions.capacity() + state.velocities.capacity()) * sizeof(softbody::Vec3) +
    state.linkRestLengths.capacity() * sizeof(double) + state.linkBroken.capacity();
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameCache::Insert(int index, const softbody::DynamicState& state)
{
  Entry& entry = this->Frames[index];
  this->MemoryUsed -= entry.Bytes; // 0 for a new entry
  entry.State = state;
  // A copy's capacity equals its size, so this is what the snapshot really costs.
  entry.Bytes = SizeOf(entry.State);
  entry.LastUse = ++this->UseClock;
  this->MemoryUsed += entry.Bytes;
  this->EvictToLimit();
}

//------------------------------------------------------------------------------
const softbody::DynamicState* vtkSoftBodyFrameCache::FindLatestAtOrBefore(
  int index, int& foundIndex)
{
  auto it = this->Frames.upper_bound(index); // first frame after `index`
  if (it == this->Frames.begin())
  {
    foundIndex = -1;
    return nullptr;
  }
  --it;
  it->second.LastUse = ++this->UseClock;
  foundIndex = it->first;
  return &it->second.State;
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameCache::DropAfter(int index)
{
  for (auto it = this->Frames.upper_bound(index); it != this->Frames.end();)
  {
    this->MemoryUsed -= it->second.Bytes;
    it = this->Frames.erase(it);
  }
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameCache::Clear()
{
  this->Frames.clear();
  this->MemoryUsed = 0;
}

//------------------------------------------------------------------------------
void vtkSoftBodyFrameCache::EvictToLimit()
{
  // A linear scan per eviction: a cache holds at most a few thousand frames, and each frame
  // it saves costs far more simulation time than the scan.
  while (this->MemoryUsed > this->MemoryLimit)
  {
    auto victim = this->Frames.end();
    for (auto it = this->Frames.begin(); it != this->Frames.end(); ++it)
    {
      if (it->first != 0 && (victim == this->Frames.end() || it->second.LastUse < victim->second.LastUse))
      {
        victim = it;
      }
    }
    if (victim == this->Frames.end())
    {
      return; // only frame 0 is left: it stays even over budget
    }
    this->MemoryUsed -= victim->second.Bytes;
    this->Frames.erase(victim);
  }
}
