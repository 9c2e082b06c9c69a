// The model the node tests share: a degree-(2, 2, 2) volume, a blob whose centre is raised (as the
// blob preset), as its control points and as a model file's text.
export const points = [];
for (let i = 0; i < 3; i++) for (let j = 0; j < 3; j++) for (let k = 0; k < 3; k++) {
  const corner = i !== 1 && j !== 1 && k !== 1;
  const centre = i === 1 && j === 1 && k === 1;
  points.push([i - 1, j - 1, k - 1, centre ? 1 : corner ? -1 : 0.25]);
}
export const MODEL = JSON.stringify({ format: 'bezsolid', version: 1, solid: { kind: 'volume', degree: [2, 2, 2], points } });
