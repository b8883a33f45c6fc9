// Collects the messages of an internal algorithm's error or warning events,
// so a filter that drives another one (the stream tracer and the adaptive
// sampler run a vtkWalkOnSpheresSolver, once per stage or round) can report
// them as its own: each distinct message once, without VTK's "Warning: In
// file, line n / class (address):" header.
// Private to the GridFree::Filters module.
#ifndef GridFreeMessageCollector_h
#define GridFreeMessageCollector_h

#include "vtkCommand.h"

#include <algorithm>
#include <string>
#include <vector>

namespace gridfree
{
class MessageCollector : public vtkCommand
{
public:
  static MessageCollector* New() { return new MessageCollector; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (!data)
    {
      return;
    }
    std::string message = static_cast<const char*>(data);
    // VTK's text is "Kind: In file, line n\nclass (address): message\n\n".
    const std::size_t header = message.find("): ");
    if (header != std::string::npos)
    {
      message = message.substr(header + 3);
    }
    while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
    {
      message.pop_back();
    }
    if (std::find(this->Messages.begin(), this->Messages.end(), message) == this->Messages.end())
    {
      this->Messages.push_back(message);
      this->Text += (this->Text.empty() ? "" : " ") + message;
    }
  }
  std::vector<std::string> Messages; // distinct, in order of arrival
  std::string Text;                  // the same, joined
};
} // namespace gridfree

#endif
