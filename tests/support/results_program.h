// The loop of a Python program that speaks the results protocol over pipes
// (`--command`, docs/other-languages.md): it reads each JSON-lines batch and
// answers every case with a miss (count 0), then writes `after_answer` (a
// Python expression, '' for nothing) and flushes.
#pragma once

#include <string>

namespace rayverify::test_support {

inline std::string miss_answering_loop(const std::string& after_answer = "''") {
    return "while True:\n"
           "    header = sys.stdin.readline()\n"
           "    if not header:\n"
           "        break\n"
           "    h = json.loads(header)\n"
           "    ids = [json.loads(sys.stdin.readline())['id'] for _ in range(h['cases'])]\n"
           "    out = [json.dumps({'rayverify': 'results', 'version': 1, 'precision': h['precision'],\n"
           "                       'fingerprint': h['fingerprint']})]\n"
           "    out += [json.dumps({'id': i, 'count': 0}) for i in ids]\n"
           "    sys.stdout.write('\\n'.join(out) + '\\n' + " + after_answer + ")\n"
           "    sys.stdout.flush()\n";
}

}  // namespace rayverify::test_support
