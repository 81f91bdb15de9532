// Node 20 cannot run TypeScript: these module hooks transpile the app's .ts files on the fly with the
// project's own TypeScript (types are checked by `npm run build`, not here).
import { readFile } from 'node:fs/promises';
import ts from 'typescript';

export async function load(url, context, nextLoad) {
  if (!url.endsWith('.ts')) return nextLoad(url, context);
  const source = await readFile(new URL(url), 'utf8');
  const out = ts.transpileModule(source, {
    fileName: url,
    compilerOptions: {
      module: ts.ModuleKind.ESNext,
      target: ts.ScriptTarget.ES2022,
      verbatimModuleSyntax: false,
      rewriteRelativeImportExtensions: false,
    },
  });
  return { format: 'module', source: out.outputText, shortCircuit: true };
}
