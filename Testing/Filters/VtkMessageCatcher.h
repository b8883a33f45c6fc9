// Records the errors and warnings a VTK object reports instead of printing
// them, so filter tests can assert on the messages users would see.
#ifndef GRIDFREE_TESTING_VTKMESSAGECATCHER_H
#define GRIDFREE_TESTING_VTKMESSAGECATCHER_H

#include "vtkCommand.h"

#include <string>

class MessageCatcher : public vtkCommand
{
public:
  static MessageCatcher* New() { return new MessageCatcher; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    const std::string text = data ? static_cast<const char*>(data) : "";
    (event == vtkCommand::ErrorEvent ? Errors : Warnings) += text;
  }
  std::string Errors, Warnings;
};

#endif
