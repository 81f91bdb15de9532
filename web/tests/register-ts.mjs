// `node --import ./tests/register-ts.mjs`: lets node's test runner import the app's .ts modules.
import { register } from 'node:module';

register('./ts-hooks.mjs', import.meta.url);
