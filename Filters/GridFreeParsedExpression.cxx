#include "GridFreeParsedExpression.h"

#include "vtkCommand.h"

namespace gridfree
{
namespace
{
// Collects the messages of a VTK object's error events instead of printing them.
class ErrorCollector : public vtkCommand
{
public:
  static ErrorCollector* New() { return new ErrorCollector; }
  void Execute(vtkObject*, unsigned long, void* callData) override
  {
    if (callData)
    {
      this->Message += static_cast<const char*>(callData);
    }
  }
  std::string Message;
};

// The parser's own words from a VTK error message ("ERROR: In FILE, line
// N\nvtkExprTkFunctionParser (0x...): Err: 0 Type: [Syntax Error] Msg:
// ERR201 - Undefined symbol: 'yy'\tExpression: x*yy"): the text after
// "Msg: " up to the echoed expression, else every line but the location.
std::string ParserReason(const std::string& message)
{
  const std::size_t msg = message.find("Msg: ");
  if (msg != std::string::npos)
  {
    std::string text = message.substr(msg + 5);
    const std::size_t end = text.find_first_of("\t\n");
    text = text.substr(0, end);
    return text.empty() ? message : text;
  }
  std::string text;
  std::size_t start = 0;
  while (start < message.size())
  {
    std::size_t end = message.find('\n', start);
    if (end == std::string::npos)
    {
      end = message.size();
    }
    std::string line = message.substr(start, end - start);
    start = end + 1;
    if (line.empty() || line.rfind("ERROR: In ", 0) == 0)
    {
      continue;
    }
    const std::size_t object = line.find("): ");
    if (line.rfind("vtk", 0) == 0 && object != std::string::npos)
    {
      line = line.substr(object + 3);
    }
    text += (text.empty() ? "" : "; ") + line;
  }
  return text.empty() ? message : text;
}
} // namespace

int ExpressionComponents(const std::string& expression, std::string& reason)
{
  vtkNew<vtkExprTkFunctionParser> parser;
  vtkNew<ErrorCollector> errors;
  parser->AddObserver(vtkCommand::ErrorEvent, errors);
  parser->SetFunction(expression.c_str());
  parser->SetScalarVariableValue("x", 0.0);
  parser->SetScalarVariableValue("y", 0.0);
  parser->SetScalarVariableValue("z", 0.0);
  if (parser->IsScalarResult())
  {
    return 1;
  }
  if (parser->IsVectorResult())
  {
    return 3;
  }
  reason = errors->Message.empty() ? std::string("it does not evaluate to a number or a vector")
                                   : ParserReason(errors->Message);
  return 0;
}

bool ExpressionReadsPosition(const std::string& expression)
{
  vtkNew<vtkExprTkFunctionParser> parser;
  vtkNew<ErrorCollector> errors; // a position it reads is an error here, not a message
  parser->AddObserver(vtkCommand::ErrorEvent, errors);
  parser->SetFunction(expression.c_str());
  return !(parser->IsScalarResult() || parser->IsVectorResult());
}
} // namespace gridfree
